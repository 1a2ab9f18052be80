// saveGltf's part for features: a mesh's feature ID sets as EXT_mesh_features, instances' as EXT_instance_features,
// and the property store they name as the root EXT_structural_metadata (GltfWriteMetadata.cpp). Internal.
#pragma once
#include "sg/core/Features.h"
#include "sg/core/Node.h"

#include <tiny_gltf.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace sg::gltf {

class MetadataWriter {
public:
    // `texture` writes a texture (once) and gives its index; `warnings` (may be null) hears what is left out.
    MetadataWriter(tinygltf::Model& m, std::function<int(const Texture&)> texture, std::vector<std::string>* warnings)
        : m_(m), texture_(std::move(texture)), warnings_(warnings) {}

    // Primitive p's EXT_mesh_features from its mesh's features: attribute sets as _FEATURE_ID_n accessors, implicit
    // and texture sets as they are. Property textures and attributes are not written (a warning says so).
    void primitive(const MeshFeatures& f, tinygltf::Primitive& p);
    // EXT_instance_features on gn, whose EXT_mesh_gpu_instancing `attributes` place `members` (Instances) in that
    // order: written when they all share one MeshFeatures (else a warning), ids as _FEATURE_ID_n attributes.
    void instances(const std::vector<const Node*>& members, tinygltf::Value::Object& attributes, tinygltf::Node& gn);
    // A node that is a feature (Node::setFeatures) and not written as an instance: its first set's feature in
    // sgkit's extras, {"table", "id", "count", "label"} (glTF has no node-level feature IDs outside instancing; other
    // readers ignore it). Null when the node is none.
    tinygltf::Value nodeFeature(const Node& n);
    // The root EXT_structural_metadata (schema and property tables) and the extensions used; once, at the end.
    void finish();

private:
    int view(const uint8_t* data, size_t size);
    int idAccessor(const std::vector<uint32_t>& ids);
    // The propertyTable member a set written against `store` may have: only the first store written is kept (a glTF
    // file has one); a set of another loses its table, with a warning.
    bool keepTable(const PropertyStore* store);
    void warn(const std::string& what);

    tinygltf::Model& m_;
    std::function<int(const Texture&)> texture_;
    std::vector<std::string>* warnings_;
    const PropertyStore* store_ = nullptr;
    std::map<const std::vector<uint32_t>*, int> idAccessors_;  // ids of shared MeshFeatures written once
    bool meshFeatures_ = false, instanceFeatures_ = false, otherStore_ = false, leftOut_ = false;
};

}  // namespace sg::gltf
