// Per-feature colours that a renderer draws with and a pick respects: a style (3D Tiles styling, or any rule a
// program gives) evaluated once per property table it meets, and a highlighted feature over it. The renderer reads
// a table's colours by feature id in its vertex stage: no mesh is copied, and restyling re-evaluates the tables
// without reloading anything.
#pragma once
#include "sg/core/Features.h"
#include "sg/core/Properties.h"

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace sg {

class FeatureStyle : public Referenced {
public:
    // Fills `rgba` (4 bytes per row of the table, preset to 255: white, shown) for table `table` of `store`. Alpha 0
    // hides a feature: neither drawn nor picked. Colours multiply the material's (3D Tiles' HIGHLIGHT blending).
    using Rule = std::function<void(const PropertyStore& store, int table, std::vector<uint8_t>& rgba)>;

    // A new rule: every table is evaluated again when next asked for. Any thread.
    void setRule(Rule rule);
    // One feature drawn in `color` whatever the rule says (a click's highlight); a null store clears it.
    void setHighlight(const PropertyStore* store, int table, int64_t feature, const vec4& color);

    struct Colors {
        std::vector<uint8_t> rgba;  // 4 per feature
        uint64_t version = 0;       // changes whenever these colours change
    };
    // The table's colours, evaluated on the first ask after a change. Any thread.
    std::shared_ptr<const Colors> colors(const PropertyStore& store, int table);
    // Whether feature `id` of the table is shown (an id past the table, or -1, is).
    bool shown(const PropertyStore& store, int table, int64_t id);
    // Whether set `set` of `features` shows feature `id` (a set without a table is always shown).
    bool shown(const MeshFeatures& features, size_t set, int64_t id);
    // Tables evaluated and kept (at most kMaxTables: the least recently asked for are dropped first).
    size_t tableCount() const;
    static constexpr size_t kMaxTables = 4096;

private:
    struct Entry {
        std::shared_ptr<const Colors> colors;
        uint64_t asked = 0;
    };
    mutable std::mutex mutex_;
    Rule rule_;
    uint64_t version_ = 1, asks_ = 0;
    struct Highlight {
        uint64_t store = 0;
        int table = -1;
        int64_t feature = -1;
        vec4 color{1.0f};
    } highlight_;
    std::map<std::pair<uint64_t, int>, Entry> tables_;  // by the store's serial and the table
};

}  // namespace sg
