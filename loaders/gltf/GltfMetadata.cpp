// glTF's feature extensions read into the kernel's types: the root EXT_structural_metadata as the file's property
// store (schema, property tables, property textures, property attribute definitions), through the metadata JSON
// reader that 3D Tiles shares. A primitive's and a node's feature ID sets are read in GltfFeatures.cpp.
#include "loaders/gltf/internal/GltfMetadata.h"
#include "loaders/gltf/internal/GltfConverter.h"
#include "loaders/metadata/internal/MetadataJson.h"

#include <cmath>
#include <cstdint>
#include <map>

namespace sg::gltf {

using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

json toJson(const tinygltf::Value& v) {
    switch (v.Type()) {
        case tinygltf::BOOL_TYPE: return v.Get<bool>();
        case tinygltf::INT_TYPE: return v.Get<int>();
        case tinygltf::REAL_TYPE: return v.Get<double>();
        case tinygltf::STRING_TYPE: return v.Get<std::string>();
        case tinygltf::ARRAY_TYPE: {
            json a = json::array();
            for (size_t i = 0; i < v.ArrayLen(); ++i) a.push_back(toJson(v.Get(int(i))));
            return a;
        }
        case tinygltf::OBJECT_TYPE: {
            json o = json::object();
            for (const std::string& k : v.Keys()) o[k] = toJson(v.Get(k));
            return o;
        }
        default: return nullptr;
    }
}

json extensionJson(const tinygltf::ExtensionMap& x, const std::string& original, const char* name) {
    auto it = x.find(name);
    if (it == x.end()) return nullptr;
    if (!original.empty()) {
        const json all = json::parse(original, nullptr, false);  // no exceptions: a discarded value on error
        if (all.is_object() && all.contains(name)) return all[name];
    }
    return toJson(it->second);
}

tinygltf::Value toValue(const json& j) {
    using tinygltf::Value;
    if (j.is_boolean()) return Value(j.get<bool>());
    if (j.is_number_integer() && j.get<int64_t>() >= INT32_MIN && j.get<int64_t>() <= INT32_MAX)
        return Value(int(j.get<int64_t>()));
    if (j.is_number()) return Value(j.get<double>());
    if (j.is_string()) return Value(j.get<std::string>());
    if (j.is_array()) {
        Value::Array a;
        for (const json& e : j) a.push_back(toValue(e));
        return Value(std::move(a));
    }
    if (j.is_object()) {
        Value::Object o;
        for (const auto& [k, e] : j.items()) o[k] = toValue(e);
        return Value(std::move(o));
    }
    return Value();
}

const json* member(const json& o, const char* key) {
    if (!o.is_object()) return nullptr;
    auto it = o.find(key);
    return it == o.end() ? nullptr : &*it;
}

int64_t integer(const std::string& file, const json& j, const std::string& path, int64_t lo, int64_t hi) {
    const double d = j.is_number() ? j.get<double>() : std::nan("");
    if (!(d == std::floor(d)) || d < double(lo) || d > double(hi))
        fail(file, path, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return j.is_number_float() ? int64_t(d) : j.get<int64_t>();
}

std::vector<uint8_t> channels(const std::string& file, const json* j, const std::string& path) {
    if (!j) return {0};  // glTF's default: the red channel
    if (!j->is_array() || j->empty()) fail(file, path, "must be a non-empty array of channels");
    std::vector<uint8_t> out;
    for (size_t k = 0; k < j->size(); ++k) out.push_back(uint8_t(integer(file, (*j)[k], at(path, k), 0, 3)));
    return out;
}

size_t elementBytes(const Schema& schema, const ClassProperty& p) {
    if (p.array && p.count == 0) return 0;  // variable length: offsets, which textures and attributes do not have
    size_t bytes = 0;
    if (p.type == PropertyType::Enum) {
        if (p.enumIndex >= 0 && size_t(p.enumIndex) < schema.enums.size())
            bytes = size_t(componentBytes(schema.enums[size_t(p.enumIndex)].valueType));
    } else if (p.type != PropertyType::String && p.type != PropertyType::Boolean) {
        bytes = size_t(componentCount(p.type)) * size_t(componentBytes(p.componentType));
    }
    return bytes * (p.array ? p.count : 1);
}

namespace {

// A definition's class (by its "class" id, which the schema must have) and its "properties" object.
struct Definition {
    int classIndex = -1;
    const json* properties = nullptr;
};

Definition definition(const std::string& file, const Schema& schema, const json& j, const std::string& path) {
    if (!j.is_object()) fail(file, path, "must be an object");
    const json* cls = member(j, "class");
    if (!cls || !cls->is_string()) fail(file, path + ".class", "must be the id of a class of the schema");
    Definition d;
    d.classIndex = schema.findClass(cls->get<std::string>());
    if (d.classIndex < 0) fail(file, path + ".class", "class '" + cls->get<std::string>() + "' is not in the schema");
    d.properties = member(j, "properties");
    if (d.properties && !d.properties->is_object()) fail(file, path + ".properties", "must be an object");
    return d;
}

std::string name(const json& j) {
    const json* n = member(j, "name");
    return n && n->is_string() ? n->get<std::string>() : std::string();
}

}  // namespace

// A property texture: each property's texture, UV set and channels. A property a texture cannot hold (a STRING,
// BOOLEAN or variable-length array, or channels of another size than its elements) is a warning, and left out.
static PropertyTextureDef propertyTexture(Converter& c, const Schema& schema, const json& j, const std::string& path) {
    const Definition d = definition(c.file, schema, j, path);
    PropertyTextureDef def;
    def.name = name(j);
    def.classIndex = d.classIndex;
    if (!d.properties) return def;
    const ClassDef& cls = schema.classes[size_t(d.classIndex)];
    const metadata::Context ctx{c.file, &c.out.warnings};
    for (const auto& [id, pj] : d.properties->items()) {
        const std::string pp = path + ".properties." + id;
        PropertyTextureDef::Property p;
        p.property = cls.find(id);
        if (p.property < 0) c.bad(pp, "class '" + cls.id + "' has no property '" + id + "'");
        const ClassProperty& cp = cls.properties[size_t(p.property)];
        const json* index = member(pj, "index");
        if (!index) c.bad(pp + ".index", "missing: a property texture needs a texture");
        const int t = int(integer(c.file, *index, pp + ".index", 0, int64_t(c.m.textures.size()) - 1));
        const json* texCoord = member(pj, "texCoord");
        p.texCoord = texCoord ? int(integer(c.file, *texCoord, pp + ".texCoord", 0, 1 << 30)) : 0;
        p.channels = channels(c.file, member(pj, "channels"), pp + ".channels");
        p.overrides = metadata::parseOverrides(pj, cp, ctx, pp);
        const size_t bytes = elementBytes(schema, cp);
        if (bytes == 0) {
            c.warn(pp, std::string("a ") + propertyTypeName(cp.type) + (cp.array ? " array" : "") +
                           " property cannot be read from a texture, left out");
            continue;
        }
        if (bytes != p.channels.size()) {
            c.warn(pp + ".channels", std::to_string(p.channels.size()) + " channels for elements of " +
                                         std::to_string(bytes) + " bytes, left out");
            continue;
        }
        if (p.texCoord > 1) {
            c.warn(pp + ".texCoord", "only UV sets 0 and 1 are read, left out");
            continue;
        }
        p.texture = c.texture(t, pp);
        if (p.texture) def.properties.push_back(std::move(p));  // else warned: the image does not decode
    }
    return def;
}

static PropertyAttributeDef propertyAttribute(Converter& c, const Schema& schema, const json& j,
                                              const std::string& path) {
    const Definition d = definition(c.file, schema, j, path);
    PropertyAttributeDef def;
    def.name = name(j);
    def.classIndex = d.classIndex;
    if (!d.properties) return def;
    const ClassDef& cls = schema.classes[size_t(d.classIndex)];
    const metadata::Context ctx{c.file, &c.out.warnings};
    for (const auto& [id, pj] : d.properties->items()) {
        const std::string pp = path + ".properties." + id;
        PropertyAttributeDef::Property p;
        p.property = cls.find(id);
        if (p.property < 0) c.bad(pp, "class '" + cls.id + "' has no property '" + id + "'");
        const json* attribute = member(pj, "attribute");
        if (!attribute || !attribute->is_string() || attribute->get<std::string>().empty())
            c.bad(pp + ".attribute", "must name a vertex attribute");
        p.attribute = attribute->get<std::string>();
        p.overrides = metadata::parseOverrides(pj, cls.properties[size_t(p.property)], ctx, pp);
        def.properties.push_back(std::move(p));
    }
    return def;
}

// The elements of the array `key` of the root extension, each parsed by `parse` with its path.
template <class F>
static void each(Converter& c, const json& x, const char* key, const std::string& path, F parse) {
    const json* a = member(x, key);
    if (!a) return;
    if (!a->is_array()) c.bad(path + "." + key, "must be an array");
    for (size_t k = 0; k < a->size(); ++k) parse((*a)[k], at(path + "." + key, k));
}

void Converter::readMetadata() {
    if (!m.extensions.count(kStructuralMetadata)) return;
    const std::string path = std::string("extensions.") + kStructuralMetadata;
    const json x = extensionJson(m.extensions, m.extensions_json_string, kStructuralMetadata);
    if (!x.is_object()) bad(path, "must be an object");
    const metadata::Context ctx{file, &out.warnings};
    const json* schema = member(x, "schema");
    if (!schema) {
        if (!member(x, "schemaUri")) bad(path, "needs a schema (or a schemaUri)");
        // An external schema would be a second file to fetch, which a glTF load does not do.
        warn(path + ".schemaUri", "an external schema is not read: the file's properties are ignored");
        externalSchema = true;
        return;
    }
    auto s = make<PropertyStore>();
    s->schema = metadata::parseSchema(*schema, ctx, path + ".schema");
    // Each buffer view a table names becomes one buffer of the store, copied once however many columns use it.
    std::map<int64_t, int> viewBuffers;
    const metadata::ViewLookup view = [&](int64_t v, const std::string& vp) {
        if (v < 0 || uint64_t(v) >= m.bufferViews.size())
            bad(vp, "bufferView " + std::to_string(v) + " does not exist (" + std::to_string(m.bufferViews.size()) +
                        " bufferViews)");
        const tinygltf::BufferView& bv = m.bufferViews[size_t(v)];
        auto [found, fresh] = viewBuffers.emplace(v, -1);
        if (fresh) {
            const auto first = m.buffers[size_t(bv.buffer)].data.begin() + std::ptrdiff_t(bv.byteOffset);
            found->second = s->addBuffer(std::vector<uint8_t>(first, first + std::ptrdiff_t(bv.byteLength)));
        }
        return ByteSpan{found->second, 0, bv.byteLength};
    };
    each(*this, x, "propertyTables", path, [&](const json& j, const std::string& tp) {
        PropertyTable t = metadata::parsePropertyTable(j, s->schema, view, ctx, tp);
        try {
            s->addTable(std::move(t));
        } catch (const std::invalid_argument& e) {
            bad(tp, e.what());
        }
    });
    each(*this, x, "propertyTextures", path, [&](const json& j, const std::string& tp) {
        s->propertyTextures.push_back(propertyTexture(*this, s->schema, j, tp));
    });
    each(*this, x, "propertyAttributes", path, [&](const json& j, const std::string& ap) {
        s->propertyAttributes.push_back(propertyAttribute(*this, s->schema, j, ap));
    });
    store = s;
}

void Converter::nodeFeature(Node& inner, const Value& feature, const std::string& path) {
    if (!feature.IsObject()) bad(path, "must be an object");
    auto whole = [&](const char* key, double hi) {
        const double v = number(feature, key, path, -1.0);
        if (v < 0 || v > hi || v != std::floor(v))
            bad(path + "." + key, "must be a whole number in [0, " + std::to_string((long long)hi) + "]");
        return v;
    };
    const uint32_t id = uint32_t(whole("id", 4294967295.0)), count = uint32_t(whole("count", 4294967295.0));
    int table = -1;
    if (feature.Has("table")) {
        table = int(whole("table", 1e9));
        if (!store || size_t(table) >= store->tables().size()) {
            warn(path + ".table", "names no property table of the file, the feature has no properties");
            table = -1;
        }
    }
    const std::string label = string(feature, "label", path, "");
    ref_ptr<MeshFeatures>& f = nodeFeatureSets[{table, count, label}];
    if (!f) {
        // Implicit: the node's index is its id (Node::setFeatures), as the writer resolved it.
        FeatureIdSet s;
        s.source = FeatureIdSet::Source::Implicit;
        s.label = label;
        s.featureCount = count;
        s.propertyTable = table;
        f = make<MeshFeatures>();
        f->sets.push_back(std::move(s));
        if (table >= 0) f->store = store;
    }
    inner.setFeatures(f, id);
}

}  // namespace sg::gltf
