// Feature ID sets read into MeshFeatures: a primitive's EXT_mesh_features (attribute, implicit and texture sets)
// and EXT_structural_metadata (property textures, property attributes' per-vertex bytes), a node's
// EXT_instance_features over its EXT_mesh_gpu_instancing instances, and a 3D Tiles 1.0 tile's batch ids.
#include "loaders/gltf/internal/GltfConverter.h"
#include "loaders/gltf/internal/GltfMetadata.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace sg::gltf {

using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

namespace {

const tinygltf::Value* extension(const tinygltf::ExtensionMap& x, const char* name) {
    auto it = x.find(name);
    return it == x.end() ? nullptr : &it->second;
}

// Feature ids of an accessor, one per vertex or instance (n): a SCALAR, not normalized, of any of glTF's component
// types; a float one must hold whole numbers, none may be negative or past uint32.
std::vector<uint32_t> readIds(const std::string& file, const tinygltf::Model& m, int acc, size_t n,
                              const std::string& path) {
    if (acc < 0 || size_t(acc) >= m.accessors.size())
        fail(file, path, "accessor " + std::to_string(acc) + " does not exist");
    const tinygltf::Accessor& a = m.accessors[size_t(acc)];
    if (a.type != TINYGLTF_TYPE_SCALAR || a.normalized)
        fail(file, path, "accessor " + std::to_string(acc) + " of feature ids must be a SCALAR, not normalized");
    if (a.count != n)
        fail(
            file, path,
            "accessor " + std::to_string(acc) + " has " + std::to_string(a.count) + " ids, needs " + std::to_string(n));
    const int c = a.componentType;
    if (c != TINYGLTF_COMPONENT_TYPE_BYTE && c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        c != TINYGLTF_COMPONENT_TYPE_SHORT && c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && c != TINYGLTF_COMPONENT_TYPE_FLOAT)
        fail(file, path,
             "accessor " + std::to_string(acc) + " has componentType " + std::to_string(c) +
                 ", which glTF does not have for an attribute");
    const AccessorReader r(m, a);
    const bool whole = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                       a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                       a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    std::vector<uint32_t> ids(n);
    if (c == TINYGLTF_COMPONENT_TYPE_FLOAT && r.base) {
        // The common case (ids written as floats, as the extension suggests), read straight: a tile's millions of
        // vertices are read here.
        bool ok = true;
        for (size_t i = 0; i < n; ++i) {
            float v;
            std::memcpy(&v, r.base + i * r.stride, sizeof v);
            ok &= v >= 0.0f && v <= 4294967040.0f && v == std::floor(v);
            ids[i] = ok ? uint32_t(v) : 0u;
        }
        if (ok) return ids;  // else the loop below finds the first bad id and names it
    }
    for (size_t i = 0; i < n; ++i) {
        if (whole) {
            ids[i] = r.index(i);
            continue;
        }
        const double v = double(r.component(i, 0));  // BYTE, SHORT and FLOAT read exactly as float
        if (!(v >= 0.0 && v <= 4294967295.0 && v == std::floor(v)))
            fail(file, path, "id " + std::to_string(i) + " (" + std::to_string(v) + ") is not a feature id");
        ids[i] = uint32_t(v);
    }
    return ids;
}

// The glTF accessor type and component type a property attribute of property `p` has (-1: none can hold it).
std::pair<int, int> accessorTypeOf(const Schema& schema, const ClassProperty& p) {
    static const int types[] = {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC2, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4,
                                TINYGLTF_TYPE_MAT2,   TINYGLTF_TYPE_MAT3, TINYGLTF_TYPE_MAT4};
    ComponentType c = p.componentType;
    int type = p.type <= PropertyType::Mat4 ? types[int(p.type)] : -1;
    if (p.type == PropertyType::Enum && p.enumIndex >= 0 && size_t(p.enumIndex) < schema.enums.size()) {
        c = schema.enums[size_t(p.enumIndex)].valueType;
        type = TINYGLTF_TYPE_SCALAR;
    }
    // Matrices of 1- and 2-byte components have padded columns in glTF: not as the store's elements are.
    const bool padded = p.type >= PropertyType::Mat2 && p.type <= PropertyType::Mat4 && componentBytes(c) < 4;
    if (p.array || padded) return {-1, -1};
    switch (c) {
        case ComponentType::Int8: return {type, TINYGLTF_COMPONENT_TYPE_BYTE};
        case ComponentType::UInt8: return {type, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE};
        case ComponentType::Int16: return {type, TINYGLTF_COMPONENT_TYPE_SHORT};
        case ComponentType::UInt16: return {type, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
        case ComponentType::UInt32: return {type, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};
        case ComponentType::Float32: return {type, TINYGLTF_COMPONENT_TYPE_FLOAT};
        default: return {-1, -1};
    }
}

// The raw bytes of each of an accessor's n elements, packed (a view's byteStride dropped; zeros without a view).
std::vector<uint8_t> rawElements(const tinygltf::Model& m, const tinygltf::Accessor& a, size_t n, size_t elem) {
    std::vector<uint8_t> out(n * elem, 0);
    if (a.bufferView < 0) return out;
    const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
    const uint8_t* base = m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
    const size_t stride = v.byteStride ? v.byteStride : elem;
    for (size_t i = 0; i < n; ++i) std::memcpy(out.data() + i * elem, base + i * stride, elem);
    return out;
}

}  // namespace

std::string Converter::featureKey(const tinygltf::Primitive& p) {
    std::string key;
    for (const auto& [name, acc] : p.attributes)
        if (!name.empty() && name[0] == '_') key += name + "=" + std::to_string(acc) + ";";
    for (const char* x : {kMeshFeatures, kStructuralMetadata})
        if (extension(p.extensions, x)) key += extensionJson(p.extensions, p.extensions_json_string, x).dump();
    return key;
}

// What every feature ID set has: featureCount, nullFeatureId, label and propertyTable (checked against the store).
static FeatureIdSet commonSet(Converter& c, const json& j, const std::string& path) {
    if (!j.is_object()) c.bad(path, "must be an object");
    FeatureIdSet s;
    const json* count = member(j, "featureCount");
    if (!count) c.bad(path + ".featureCount", "missing");
    s.featureCount = uint32_t(integer(c.file, *count, path + ".featureCount", 1, UINT32_MAX));
    if (const json* nul = member(j, "nullFeatureId")) {
        s.hasNullFeatureId = true;
        s.nullFeatureId = uint32_t(integer(c.file, *nul, path + ".nullFeatureId", 0, UINT32_MAX));
    }
    if (const json* label = member(j, "label"); label && label->is_string()) s.label = label->get<std::string>();
    if (const json* table = member(j, "propertyTable")) {
        const int64_t t = integer(c.file, *table, path + ".propertyTable", 0, INT32_MAX);
        if (c.externalSchema) return s;  // warned: the file's properties are ignored
        const size_t have = c.store ? c.store->tables().size() : 0;
        if (size_t(t) >= have)
            c.bad(path + ".propertyTable", "property table " + std::to_string(t) + " does not exist (" +
                                               std::to_string(have) + " in the file's EXT_structural_metadata)");
        s.propertyTable = int(t);
    }
    return s;
}

// A texture set: its texture, UV set (0 or 1) and channels. False (with a warning) when it cannot be read.
static bool textureSet(Converter& c, const json& j, const std::string& path, FeatureIdSet& s) {
    const json* index = member(j, "index");
    if (!index) c.bad(path + ".index", "missing");
    const int64_t t = integer(c.file, *index, path + ".index", 0, INT32_MAX);
    if (size_t(t) >= c.m.textures.size())
        c.bad(path + ".index", "texture " + std::to_string(t) + " does not exist (" +
                                   std::to_string(c.m.textures.size()) + " textures)");
    const json* texCoord = member(j, "texCoord");
    s.texCoord = texCoord ? int(integer(c.file, *texCoord, path + ".texCoord", 0, INT32_MAX)) : 0;
    s.channels = channels(c.file, member(j, "channels"), path + ".channels");
    s.source = FeatureIdSet::Source::Texture;
    if (s.texCoord > 1) {
        c.warn(path + ".texCoord", "only UV sets 0 and 1 are read, feature ID set left out");
        return false;
    }
    s.texture = c.texture(int(t), path);
    return bool(s.texture);  // else warned: the image does not decode
}

// Property attribute `a` of the store, its values read from primitive p's attributes.
static PropertyAttributeValues attributeValues(Converter& c, const tinygltf::Primitive& p, size_t a, size_t n,
                                               const std::string& path) {
    const PropertyAttributeDef& def = c.store->propertyAttributes[a];
    const ClassDef& cls = c.store->schema.classes[size_t(def.classIndex)];
    PropertyAttributeValues values;
    values.propertyAttribute = int(a);
    for (const PropertyAttributeDef::Property& dp : def.properties) {
        const ClassProperty& cp = cls.properties[size_t(dp.property)];
        auto it = p.attributes.find(dp.attribute);
        if (it == p.attributes.end())
            c.bad(path, "attribute '" + dp.attribute + "' (property '" + cp.id + "') is missing from the primitive");
        const std::string ap = path.substr(0, path.find(".extensions")) + ".attributes." + dp.attribute;
        const tinygltf::Accessor& acc = c.m.accessors[size_t(it->second)];
        const auto [type, comp] = accessorTypeOf(c.store->schema, cp);
        if (type < 0 || acc.type != type || acc.componentType != comp || acc.count != n)
            c.bad(ap, "accessor " + std::to_string(it->second) + " (type " + std::to_string(acc.type) +
                          ", componentType " + std::to_string(acc.componentType) + ", count " +
                          std::to_string(acc.count) + ") does not hold property '" + cp.id + "' (" +
                          propertyTypeName(cp.type) + " " + componentTypeName(cp.componentType) + ") per vertex");
        const size_t elem = elementBytes(c.store->schema, cp);
        values.columns.push_back({rawElements(c.m, acc, n, elem), uint32_t(elem)});
    }
    return values;
}

// Primitive p's EXT_structural_metadata: its property textures and attributes, by index into the store's.
static void primitiveMetadata(Converter& c, const json& x, const tinygltf::Primitive& p, size_t n,
                              const std::string& path, MeshFeatures& f) {
    for (const char* key : {"propertyTextures", "propertyAttributes"}) {
        const json* list = member(x, key);
        if (!list) continue;
        const std::string lp = path + "." + key;
        if (!list->is_array()) c.bad(lp, "must be an array of indices");
        if (c.externalSchema) continue;  // warned: the file's properties are ignored
        const bool textures = key[8] == 'T';
        const size_t have = !c.store   ? 0
                            : textures ? c.store->propertyTextures.size()
                                       : c.store->propertyAttributes.size();
        for (size_t k = 0; k < list->size(); ++k) {
            const int64_t i = integer(c.file, (*list)[k], at(lp, k), 0, INT32_MAX);
            if (size_t(i) >= have)
                c.bad(at(lp, k), std::string(key) + " " + std::to_string(i) + " does not exist (" +
                                     std::to_string(have) + " in the file's EXT_structural_metadata)");
            if (textures)
                f.propertyTextures.push_back(int(i));
            else
                f.propertyAttributes.push_back(attributeValues(c, p, size_t(i), n, at(lp, k)));
        }
    }
}

ref_ptr<MeshFeatures> Converter::primitiveFeatures(const tinygltf::Primitive& p, size_t n, const std::string& path) {
    auto f = make<MeshFeatures>();
    const tinygltf::Value* features = extension(p.extensions, kMeshFeatures);
    const tinygltf::Value* metadata = extension(p.extensions, kStructuralMetadata);
    if (features) {
        const std::string xp = path + ".extensions." + kMeshFeatures + ".featureIds";
        const json x = extensionJson(p.extensions, p.extensions_json_string, kMeshFeatures);
        const json* ids = member(x, "featureIds");
        if (!ids || !ids->is_array() || ids->empty()) bad(xp, "must be a non-empty array of feature ID sets");
        for (size_t k = 0; k < ids->size(); ++k) {
            const json& j = (*ids)[k];
            const std::string sp = at(xp, k);
            FeatureIdSet s = commonSet(*this, j, sp);
            if (const json* a = member(j, "attribute")) {
                const std::string name =
                    "_FEATURE_ID_" + std::to_string(integer(file, *a, sp + ".attribute", 0, 1 << 20));
                auto it = p.attributes.find(name);
                if (it == p.attributes.end()) bad(sp + ".attribute", "the primitive has no attribute " + name);
                s.ids = readIds(file, m, it->second, n, path + ".attributes." + name);
            } else if (const json* t = member(j, "texture")) {
                if (!textureSet(*this, *t, sp + ".texture", s)) continue;
            } else {
                s.source = FeatureIdSet::Source::Implicit;
            }
            f->sets.push_back(std::move(s));
        }
    } else if (const GltfLoadOptions& o = progress.options(); o.batchTable && !metadata) {
        // A 3D Tiles 1.0 tile: its batch ids name rows of its batch table.
        auto it = p.attributes.find("_BATCHID");
        if (it == p.attributes.end()) it = p.attributes.find("BATCH_ID");
        if (it != p.attributes.end()) {
            FeatureIdSet s;
            s.ids = readIds(file, m, it->second, n, path + ".attributes." + it->first);
            const bool table = !o.batchTable->tables().empty();
            uint32_t count = 0;
            for (uint32_t id : s.ids) count = std::max(count, id + 1);  // without a table: the ids seen
            s.featureCount = table ? uint32_t(std::min<uint64_t>(o.batchTable->tables()[0].count, UINT32_MAX)) : count;
            s.propertyTable = table ? 0 : -1;
            f->sets.push_back(std::move(s));
            f->store = o.batchTable;
            return f;
        }
    }
    if (metadata) {
        const std::string xp = path + ".extensions." + kStructuralMetadata;
        const json x = extensionJson(p.extensions, p.extensions_json_string, kStructuralMetadata);
        if (!x.is_object()) bad(xp, "must be an object");
        primitiveMetadata(*this, x, p, n, xp, *f);
    }
    if (f->sets.empty() && f->propertyTextures.empty() && f->propertyAttributes.empty()) return {};
    f->store = store;
    return f;
}

ref_ptr<MeshFeatures> Converter::instanceFeatures(int i, size_t n, const std::string& path) {
    const tinygltf::Node& gn = m.nodes[size_t(i)];
    const tinygltf::Value* features = extension(gn.extensions, kInstanceFeatures);
    if (!features) return {};
    const std::string xp = path + ".extensions." + kInstanceFeatures + ".featureIds";
    const json x = extensionJson(gn.extensions, gn.extensions_json_string, kInstanceFeatures);
    const json* ids = member(x, "featureIds");
    if (!ids || !ids->is_array() || ids->empty()) bad(xp, "must be a non-empty array of feature ID sets");
    const Value& attributes = instancing(gn)->Get("attributes");
    auto f = make<MeshFeatures>();
    for (size_t k = 0; k < ids->size(); ++k) {
        const std::string sp = at(xp, k);
        FeatureIdSet s = commonSet(*this, (*ids)[k], sp);
        s.source = FeatureIdSet::Source::Instance;
        if (const json* a = member((*ids)[k], "attribute")) {
            const std::string name = "_FEATURE_ID_" + std::to_string(integer(file, *a, sp + ".attribute", 0, 1 << 20));
            if (!attributes.Has(name))
                bad(sp + ".attribute", std::string("the node's ") + kInstancing + " has no attribute " + name);
            s.ids = readIds(file, m, attributes.Get(name).GetNumberAsInt(), n,
                            path + ".extensions." + kInstancing + ".attributes." + name);
        } else {  // implicit: the instance's index
            s.ids.resize(n);
            for (size_t v = 0; v < n; ++v) s.ids[v] = uint32_t(v);
        }
        f->sets.push_back(std::move(s));
    }
    f->store = store;
    return f;
}

}  // namespace sg::gltf
