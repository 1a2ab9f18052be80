#include "sg/style/FeatureStyle.h"

#include <algorithm>
#include <cmath>

namespace sg {
namespace {

uint8_t byte(float v) { return uint8_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

void FeatureStyle::setRule(Rule rule) {
    std::lock_guard<std::mutex> lock(mutex_);
    rule_ = std::move(rule);
    tables_.clear();
    ++version_;
}

void FeatureStyle::setHighlight(const PropertyStore* store, int table, int64_t feature, const vec4& color) {
    std::lock_guard<std::mutex> lock(mutex_);
    // Only the tables of the old and the new highlight change.
    const std::pair<uint64_t, int> before{highlight_.store, highlight_.table};
    highlight_ = store ? Highlight{store->serial(), table, feature, color} : Highlight{};
    tables_.erase(before);
    tables_.erase({highlight_.store, highlight_.table});
    ++version_;
}

std::shared_ptr<const FeatureStyle::Colors> FeatureStyle::colors(const PropertyStore& store, int table) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::pair<uint64_t, int> key{store.serial(), table};
    auto it = tables_.find(key);
    if (it != tables_.end()) {
        it->second.asked = ++asks_;
        return it->second.colors;
    }
    auto c = std::make_shared<Colors>();
    c->version = version_;
    const uint64_t rows = table >= 0 && size_t(table) < store.tables().size() ? store.tables()[size_t(table)].count : 0;
    c->rgba.assign(size_t(rows) * 4, 255);
    if (rule_ && rows > 0) rule_(store, table, c->rgba);
    c->rgba.resize(size_t(rows) * 4, 255);  // a rule that changed the size gets its rows back
    if (highlight_.store == key.first && highlight_.table == table && highlight_.feature >= 0 &&
        uint64_t(highlight_.feature) < rows) {
        uint8_t* px = c->rgba.data() + size_t(highlight_.feature) * 4;
        for (int k = 0; k < 4; ++k) px[k] = byte(highlight_.color[k]);
    }
    if (tables_.size() >= kMaxTables) {
        auto oldest = std::min_element(tables_.begin(), tables_.end(),
                                       [](const auto& a, const auto& b) { return a.second.asked < b.second.asked; });
        tables_.erase(oldest);
    }
    tables_[key] = Entry{c, ++asks_};
    return c;
}

bool FeatureStyle::shown(const PropertyStore& store, int table, int64_t id) {
    if (id < 0) return true;
    const std::shared_ptr<const Colors> c = colors(store, table);
    return size_t(id) * 4 + 3 >= c->rgba.size() || c->rgba[size_t(id) * 4 + 3] != 0;
}

bool FeatureStyle::shown(const MeshFeatures& features, size_t set, int64_t id) {
    if (!features.store || set >= features.sets.size() || features.sets[set].propertyTable < 0) return true;
    return shown(*features.store, features.sets[set].propertyTable, id);
}

size_t FeatureStyle::tableCount() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return tables_.size();
}

}  // namespace sg
