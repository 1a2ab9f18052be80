// Feature ID sets and their property store written as glTF's EXT_mesh_features, EXT_instance_features and
// EXT_structural_metadata. One store per file, as the extension allows: the first one a set names is written, and
// sets of other stores keep their ids without a table (merging schemas would rename classes a reader looks for).
#include "loaders/gltf/internal/GltfWriteMetadata.h"

#include "loaders/gltf/internal/GltfDetail.h"
#include "loaders/gltf/internal/GltfMetadata.h"
#include "loaders/metadata/internal/MetadataJson.h"
#include "nodes/Instance.h"

#include <algorithm>

namespace sg::gltf {

using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

void MetadataWriter::warn(const std::string& what) {
    if (warnings_) warnings_->push_back(what);
}

int MetadataWriter::view(const uint8_t* data, size_t size) {
    if (m_.buffers.empty()) m_.buffers.emplace_back();
    auto& b = m_.buffers[0].data;
    b.resize((b.size() + 7) & ~size_t(7), 0);  // EXT_structural_metadata: views at multiples of 8 bytes
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = b.size();
    v.byteLength = size;
    b.insert(b.end(), data, data + size);
    m_.bufferViews.push_back(v);
    return int(m_.bufferViews.size() - 1);
}

// Ids as floats while float holds them exactly (a vertex attribute's usual type), else as uint32.
int MetadataWriter::idAccessor(const std::vector<uint32_t>& ids) {
    auto found = idAccessors_.find(&ids);
    if (found != idAccessors_.end()) return found->second;
    const uint32_t largest = ids.empty() ? 0 : *std::max_element(ids.begin(), ids.end());
    tinygltf::Accessor a;
    a.type = TINYGLTF_TYPE_SCALAR;
    a.count = ids.size();
    if (largest <= (1u << 24)) {
        std::vector<float> f(ids.begin(), ids.end());
        a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        a.bufferView = view(reinterpret_cast<const uint8_t*>(f.data()), f.size() * sizeof(float));
    } else {
        a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        a.bufferView = view(reinterpret_cast<const uint8_t*>(ids.data()), ids.size() * sizeof(uint32_t));
    }
    m_.accessors.push_back(a);
    return idAccessors_[&ids] = int(m_.accessors.size() - 1);
}

bool MetadataWriter::keepTable(const PropertyStore* store) {
    if (!store) return false;
    if (!store_) store_ = store;
    if (store == store_) return true;
    if (!otherStore_)
        warn(
            "saveGltf(): feature ID sets of a second property store are written without their table "
            "(a glTF file holds one EXT_structural_metadata)");
    otherStore_ = true;
    return false;
}

// What every set has: featureCount, nullFeatureId, label, propertyTable.
static json commonJson(const FeatureIdSet& s, bool table) {
    json j = {{"featureCount", s.featureCount}};
    if (s.hasNullFeatureId) j["nullFeatureId"] = s.nullFeatureId;
    if (!s.label.empty()) j["label"] = s.label;
    if (table && s.propertyTable >= 0) j["propertyTable"] = s.propertyTable;
    return j;
}

void MetadataWriter::primitive(const MeshFeatures& f, tinygltf::Primitive& p) {
    if ((!f.propertyTextures.empty() || !f.propertyAttributes.empty()) && !leftOut_) {
        warn("saveGltf(): property textures and property attributes are not written");
        leftOut_ = true;
    }
    json sets = json::array();
    int attribute = 0;
    for (const FeatureIdSet& s : f.sets) {
        if (s.source == FeatureIdSet::Source::Instance) continue;  // an Instance's, not a vertex's
        if (s.source == FeatureIdSet::Source::Texture && !s.texture) continue;
        json j = commonJson(s, s.propertyTable >= 0 && keepTable(f.store.get()));
        if (s.source == FeatureIdSet::Source::Attribute) {
            p.attributes["_FEATURE_ID_" + std::to_string(attribute)] = idAccessor(s.ids);
            j["attribute"] = attribute++;
        } else if (s.source == FeatureIdSet::Source::Texture) {
            j["texture"] = {{"index", texture_(*s.texture)}, {"texCoord", s.texCoord}, {"channels", s.channels}};
        }
        sets.push_back(std::move(j));
    }
    if (sets.empty()) return;
    p.extensions[kMeshFeatures] = toValue(json{{"featureIds", std::move(sets)}});
    meshFeatures_ = true;
}

void MetadataWriter::instances(const std::vector<const Node*>& members, tinygltf::Value::Object& attributes,
                               tinygltf::Node& gn) {
    const MeshFeatures* f = members.empty() ? nullptr : static_cast<const Instance*>(members[0])->features();
    bool any = false, shared = true;
    for (const Node* n : members) {
        const MeshFeatures* g = static_cast<const Instance*>(n)->features();
        any |= g != nullptr;
        shared &= g == f;
    }
    if (!any) return;
    if (!shared) {
        warn("saveGltf(): instances with differing feature ID sets are written without them");
        return;
    }
    json sets = json::array();
    for (const FeatureIdSet& s : f->sets) {
        if (s.source != FeatureIdSet::Source::Instance) continue;
        std::vector<uint32_t> ids;
        for (const Node* n : members) {
            const uint32_t k = static_cast<const Instance*>(n)->featureIndex();
            ids.push_back(k < s.ids.size() ? s.ids[k] : (s.hasNullFeatureId ? s.nullFeatureId : 0));
        }
        json j = commonJson(s, s.propertyTable >= 0 && keepTable(f->store.get()));
        const std::string name = "_FEATURE_ID_" + std::to_string(sets.size());
        const int acc = idAccessor(ids);
        idAccessors_.erase(&ids);  // a local: its address means nothing once it is gone
        attributes[name] = tinygltf::Value(acc);
        j["attribute"] = int(sets.size());
        sets.push_back(std::move(j));
    }
    if (sets.empty()) return;
    gn.extensions[kInstanceFeatures] = toValue(json{{"featureIds", std::move(sets)}});
    instanceFeatures_ = true;
}

tinygltf::Value MetadataWriter::nodeFeature(const Node& n) {
    const MeshFeatures* f = n.features();
    if (!f || f->sets.empty()) return {};
    if (f->sets.size() > 1) warn("saveGltf(): a node's feature ID sets after its first are not written");
    const FeatureIdSet& s = f->sets[0];
    json j = {{"id", f->idAt(0, n.featureIndex())}, {"count", s.featureCount}};
    if (s.propertyTable >= 0 && keepTable(f->store.get())) j["table"] = s.propertyTable;
    if (!s.label.empty()) j["label"] = s.label;
    return toValue(j);
}

void MetadataWriter::finish() {
    auto use = [&](const char* x) {
        if (std::find(m_.extensionsUsed.begin(), m_.extensionsUsed.end(), x) == m_.extensionsUsed.end())
            m_.extensionsUsed.push_back(x);
    };
    if (meshFeatures_) use(kMeshFeatures);
    if (instanceFeatures_) use(kInstanceFeatures);
    if (!store_) return;
    const PropertyStore& s = *store_;
    json tables = json::array();
    for (const PropertyTable& t : s.tables()) {
        const ClassDef& cls = s.schema.classes[size_t(t.classIndex)];
        json props = json::object();
        for (const PropertyColumn& c : t.columns) {
            json j;
            auto span = [&](const char* key, const ByteSpan& b) {
                if (b.present()) j[key] = view(s.buffer(b.buffer).data() + b.offset, size_t(b.size));
            };
            span("values", c.values);
            span("arrayOffsets", c.arrayOffsets);
            span("stringOffsets", c.stringOffsets);
            if (c.arrayOffsets.present() && c.arrayOffsetType != ComponentType::UInt32)
                j["arrayOffsetType"] = componentTypeName(c.arrayOffsetType);
            if (c.stringOffsets.present() && c.stringOffsetType != ComponentType::UInt32)
                j["stringOffsetType"] = componentTypeName(c.stringOffsetType);
            const std::pair<const char*, const PropertyValue*> overrides[] = {{"offset", &c.overrides.offset},
                                                                              {"scale", &c.overrides.scale},
                                                                              {"min", &c.overrides.min},
                                                                              {"max", &c.overrides.max}};
            for (const auto& [key, v] : overrides)
                if (!v->isNull()) j[key] = metadata::jsonOf(*v);
            props[cls.properties[size_t(c.property)].id] = std::move(j);
        }
        json tj = {{"class", cls.id}, {"count", t.count}, {"properties", std::move(props)}};
        if (!t.name.empty()) tj["name"] = t.name;
        tables.push_back(std::move(tj));
    }
    json x = {{"schema", metadata::schemaJson(s.schema)}};
    if (!tables.empty()) x["propertyTables"] = std::move(tables);
    m_.extensions[kStructuralMetadata] = toValue(x);
    use(kStructuralMetadata);
}

}  // namespace sg::gltf
