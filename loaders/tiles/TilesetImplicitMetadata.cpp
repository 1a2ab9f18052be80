// Implicit tiles' tile and content metadata (3D Tiles 1.1): the subtree's tileMetadata and contentMetadata tables
// in the binary form glTF's EXT_structural_metadata shares, read by the shared metadata reader into a property
// store; a table's rows are its available tiles (or contents) in the order of their availability bits.
#include "loaders/tiles/internal/TilesetImplicitMetadata.h"

#include "loaders/metadata/internal/MetadataJson.h"

#include <nlohmann/json.hpp>

#include <map>
#include <stdexcept>

namespace sg::tiles {
namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& reason) {
    throw LoadError(file, path, reason);
}

// The subtree's property tables that its metadata names, each read into the store once.
class Tables {
public:
    Tables(const std::string& file, const json& doc, const SubtreeViews& views, PropertyStore& store,
           std::vector<std::string>& warnings)
        : file_(file), views_(views), store_(store), warnings_(warnings) {
        tables_ = doc.value("propertyTables", json::array());
        if (!tables_.is_array()) fail(file_, "propertyTables", "must be an array");
    }

    // The store's table for the subtree table whose index is `index` (named at `path`), checked to hold `rows`
    // rows, one per available `what`.
    int table(const json& index, const std::string& path, uint64_t rows, const std::string& what) {
        if (tables_.empty()) fail(file_, path, "names a property table, but there are none");
        if (!index.is_number_unsigned() || index.get<uint64_t>() >= tables_.size())
            fail(file_, path, "missing, or not an integer from 0 to " + std::to_string(tables_.size() - 1));
        const uint64_t t = index.get<uint64_t>();
        const std::string tp = "propertyTables[" + std::to_string(t) + "]";
        // The count first: a wrong one is the likelier fault than columns too short for it.
        const json& j = tables_[size_t(t)];
        const json n = j.is_object() ? j.value("count", json()) : json();
        if (n.is_number_unsigned() && n.get<uint64_t>() != rows)
            fail(file_, tp + ".count",
                 std::to_string(n.get<uint64_t>()) + " rows, not one per the subtree's " + std::to_string(rows) +
                     " available " + what + " (" + path + ")");
        auto found = read_.find(t);
        if (found == read_.end()) found = read_.emplace(t, add(j, tp)).first;
        return found->second;
    }

private:
    int add(const json& j, const std::string& tp) {
        // Each buffer view a column names becomes one buffer of the store, copied once however many use it.
        const metadata::ViewLookup lookup = [this](int64_t v, const std::string& at) {
            const auto [bytes, size] = views_(v >= 0 ? json(uint64_t(v)) : json(v), at);  // as the JSON had it
            auto it = viewBuffers_.find(v);
            if (it == viewBuffers_.end())
                it = viewBuffers_.emplace(v, store_.addBuffer(std::vector<uint8_t>(bytes, bytes + size))).first;
            return ByteSpan{it->second, 0, size};
        };
        std::vector<std::string> warnings;
        PropertyTable t = metadata::parsePropertyTable(nlohmann::ordered_json(j), store_.schema, lookup,
                                                       metadata::Context{file_, &warnings}, tp);
        warnings_.insert(warnings_.end(), warnings.begin(), warnings.end());
        try {
            return store_.addTable(std::move(t));
        } catch (const std::invalid_argument& e) {
            fail(file_, tp, e.what());
        }
    }

    const std::string& file_;
    const SubtreeViews& views_;
    PropertyStore& store_;
    std::vector<std::string>& warnings_;
    json tables_;
    std::map<uint64_t, int> read_;        // subtree table -> store table
    std::map<int64_t, int> viewBuffers_;  // buffer view -> store buffer
};

// Row `row` of the store's table `table` as an entity: the properties the table gives or whose default applies,
// as an entity of tileset.json holds them.
MetadataEntity entity(const PropertyStore& store, int table, uint64_t row) {
    const PropertyTable& t = store.tables()[size_t(table)];
    const ClassDef& cls = store.schema.classes[size_t(t.classIndex)];
    MetadataEntity e;
    e.classId = cls.id;
    for (size_t p = 0; p < cls.properties.size(); ++p)
        if (t.column(int(p)) || !cls.properties[p].defaultValue.isNull())
            e.properties.emplace_back(cls.properties[p].id, store.value(table, row, int(p)));
    return e;
}

}  // namespace

void readSubtreeMetadata(const std::string& file, const json& doc, const ImplicitTiling& tiling, uint64_t tiles,
                         const SubtreeViews& views, Subtree& s) {
    const bool tileMetadata = doc.contains("tileMetadata"), contentMetadata = doc.contains("contentMetadata");
    if (!tileMetadata && !contentMetadata) return;
    if (!tiling.fullSchema) {
        // Tile metadata without a schema fails its semantics' check; a tiling made by hand may have no schema.
        if (contentMetadata)
            fail(file, "contentMetadata", "metadata without a schema (the tileset has neither schema nor schemaUri)");
        return;
    }
    auto store = make<PropertyStore>();
    store->schema = *tiling.fullSchema;
    Tables tables(file, doc, views, *store, s.warnings);
    if (tileMetadata)
        s.tileTable = tables.table(doc["tileMetadata"], "tileMetadata", s.tiles.countBits(tiles), "tiles");
    s.contentTables.assign(s.contents.size(), -1);
    if (contentMetadata) {
        const json& cm = doc["contentMetadata"];
        if (!cm.is_array()) fail(file, "contentMetadata", "must be an array of property table indices");
        if (cm.size() > s.contents.size())
            fail(file, "contentMetadata",
                 std::to_string(cm.size()) + " tables for the tiling's " + std::to_string(s.contents.size()) +
                     " contents");
        for (size_t c = 0; c < cm.size(); ++c)
            s.contentTables[c] =
                tables.table(cm[c], "contentMetadata[" + std::to_string(c) + "]", s.contents[c].countBits(tiles),
                             "contents of content " + std::to_string(c));
    }
    s.store = store;
}

ref_ptr<const TileMetadata> implicitTileMetadata(const ImplicitTiling& tiling, const Subtree& s, uint64_t at,
                                                 const TileMetadata* own) {
    auto m = make<TileMetadata>();
    if (s.tileTable >= 0 && s.tiles[at])
        m->tile = entity(*s.store, s.tileTable, s.tiles.rank(at));
    else if (own)
        m->tile = own->tile;
    bool any = m->tile.has_value();
    for (size_t c = 0; c < s.contents.size(); ++c) {
        if (!s.contents[c][at]) continue;
        TileMetadata::Content content;
        const int table = c < s.contentTables.size() ? s.contentTables[c] : -1;
        if (table >= 0) content.metadata = entity(*s.store, table, s.contents[c].rank(at));
        content.group = c < tiling.contentGroups.size() ? tiling.contentGroups[c] : -1;
        any = any || content.metadata || content.group >= 0;
        m->contents.push_back(std::move(content));
    }
    if (!any) return nullptr;
    m->schema = tiling.fullSchema;
    m->groups = tiling.groups;
    return m;
}

}  // namespace sg::tiles
