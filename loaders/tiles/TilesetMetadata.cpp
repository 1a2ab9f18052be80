// 3D Tiles 1.1 metadata entities of tileset.json: the tileset's, its groups', its tiles' and contents'. Values
// come as JSON in their raw form; the schema's transforms make them what a program reads.
#include "loaders/tiles/internal/TilesetMetadata.h"

#include "loaders/metadata/internal/MetadataJson.h"

#include <nlohmann/json.hpp>

#include <algorithm>

namespace sg {

const PropertyValue* MetadataEntity::find(const std::string& id) const {
    for (const auto& [name, v] : properties)
        if (name == id) return &v;
    return nullptr;
}

const TileMetadata* tileMetadataOf(const Node& n) {
    // Depth-bounded: first parents lead to the root, but a graph edited into a cycle must not hang.
    const Node* at = &n;
    for (int depth = 0; at && depth < 4096; ++depth) {
        if (const auto* c = dynamic_cast<const TileContent*>(at)) return c->metadata.get();
        at = at->numParents() > 0 ? at->parent(0) : nullptr;
    }
    return nullptr;
}

namespace tiles {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& reason) {
    throw LoadError(file, path, reason);
}

// One element (not an array) of the property's type.
bool elementFits(const ClassProperty& p, const json& v, const Schema* schema) {
    switch (p.type) {
        case PropertyType::Boolean: return v.is_boolean();
        case PropertyType::String: return v.is_string();
        case PropertyType::Enum: {
            if (!v.is_string() || !schema || p.enumIndex < 0 || size_t(p.enumIndex) >= schema->enums.size())
                return false;
            for (const auto& [name, value] : schema->enums[size_t(p.enumIndex)].values)
                if (name == v.get_ref<const std::string&>()) return true;
            return false;
        }
        case PropertyType::Scalar: return v.is_number();
        default:
            return v.is_array() && v.size() == size_t(componentCount(p.type)) &&
                   std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_number(); });
    }
}

bool fits(const ClassProperty& p, const json& v, const Schema* schema) {
    if (!p.array) return elementFits(p, v, schema);
    if (!v.is_array() || (p.count > 0 && v.size() != p.count)) return false;
    return std::all_of(v.begin(), v.end(), [&](const json& e) { return elementFits(p, e, schema); });
}

MetadataEntity readEntityIn(const std::string& file, const json& j, const Schema& schema, const std::string& path,
                            std::vector<std::string>& warnings) {
    if (!j.is_object()) fail(file, path, "must be an object");
    const auto cls = j.find("class");
    if (cls == j.end() || !cls->is_string()) fail(file, path + ".class", "missing or not a string");
    const int c = schema.findClass(cls->get<std::string>());
    if (c < 0) fail(file, path + ".class", "class " + cls->get<std::string>() + " is not in the schema");
    const ClassDef& def = schema.classes[size_t(c)];
    const json props = j.value("properties", json::object());
    if (!props.is_object()) fail(file, path + ".properties", "must be an object");
    for (const auto& [name, v] : props.items())
        if (def.find(name) < 0)
            warnings.push_back(file + ": " + path + ".properties." + name + ": not a property of class " + def.id);
    MetadataEntity e;
    e.classId = def.id;
    for (const ClassProperty& p : def.properties) {
        const std::string pp = path + ".properties." + p.id;
        const auto v = props.find(p.id);
        if (v == props.end()) {
            if (p.required) fail(file, pp, "missing: class " + def.id + " requires it");
            if (!p.defaultValue.isNull()) e.properties.emplace_back(p.id, p.defaultValue);
            continue;
        }
        if (!fits(p, *v, &schema))
            fail(file, pp,
                 std::string("is not a ") + (p.array ? "array of " : "") + propertyTypeName(p.type) +
                     " value of the class");
        e.properties.emplace_back(p.id, entityValue(schema, p, *v));
    }
    return e;
}

}  // namespace

PropertyValue entityValue(const Schema& schema, const ClassProperty& p, const json& v) {
    PropertyValue raw = metadata::valueOf(nlohmann::ordered_json(v));
    // JSON names an enum's value (the store's bytes hold its integer).
    if (p.type == PropertyType::Enum) return !p.noData.isNull() && raw == p.noData ? p.defaultValue : raw;
    return propertyValueOf(schema, p, std::move(raw));
}

MetadataEntity readEntity(const std::string& file, const json& j, const Schema* schema, const std::string& path,
                          std::vector<std::string>& warnings) {
    if (!schema) fail(file, path, "metadata without a schema (the tileset has neither schema nor schemaUri)");
    return readEntityIn(file, j, *schema, path, warnings);
}

FileMetadata readFileMetadata(const std::string& file, const json& tileset, std::shared_ptr<const Schema> schema,
                              std::vector<std::string>& warnings) {
    FileMetadata m;
    m.schema = std::move(schema);
    auto groups = std::make_shared<std::vector<MetadataEntity>>();
    if (const auto g = tileset.find("groups"); g != tileset.end()) {
        if (!g->is_array()) fail(file, "groups", "must be an array of metadata entities");
        for (size_t i = 0; i < g->size(); ++i)
            groups->push_back(readEntity(file, (*g)[i], m.schema.get(), "groups[" + std::to_string(i) + "]", warnings));
    }
    m.groups = std::move(groups);
    if (const auto md = tileset.find("metadata"); md != tileset.end())
        m.metadata = readEntity(file, *md, m.schema.get(), "metadata", warnings);
    return m;
}

}  // namespace tiles
}  // namespace sg
