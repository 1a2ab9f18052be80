// Feature ID sets: which feature of a file's property store each vertex, texel or instance belongs to (glTF
// EXT_mesh_features and EXT_instance_features, a 3D Tiles 1.0 tile's BATCH_ID), and the per-vertex values of
// property attributes. A Mesh carries them, or nodes that are one feature each (Node::setFeatures); a pick reads them
// (sg/intersect/HitFeatures.h).
#pragma once
#include "sg/core/Properties.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sg {

struct FeatureIdSet {
    // Attribute: ids[vertex]. Implicit: the vertex index is the id. Texture: channels of a texture at a UV set,
    // nearest texel. Instance: ids[index] of a node that names its index (Node::setFeatures: an instance, a
    // building, a machine).
    enum class Source : uint8_t { Attribute, Implicit, Texture, Instance };
    Source source = Source::Attribute;
    std::string label;          // empty when the file gives none
    uint32_t featureCount = 0;  // distinct features the set names (the file's featureCount)
    bool hasNullFeatureId = false;
    uint32_t nullFeatureId = 0;     // an id that means "no feature", when hasNullFeatureId
    int propertyTable = -1;         // into the store's tables; -1: the set has no properties
    std::vector<uint32_t> ids;      // Attribute, Instance
    ref_ptr<Texture> texture;       // Texture
    int texCoord = 0;               // Texture: 0 or 1 (Mesh::uvs(), Mesh::uvs1())
    std::vector<uint8_t> channels;  // Texture: 0..3 (R, G, B, A), little-endian in that order
};

// One property attribute the mesh's vertices carry: raw bytes, `stride` per vertex, per property of the definition.
struct PropertyAttributeValues {
    int propertyAttribute = -1;  // into PropertyStore::propertyAttributes
    struct Column {
        std::vector<uint8_t> bytes;
        uint32_t stride = 0;
    };
    std::vector<Column> columns;  // one per PropertyAttributeDef::properties entry
};

// Everything a mesh (or the instances of one glTF node or i3dm) says about its features. Shared, read-only once built.
class MeshFeatures : public Referenced {
public:
    std::vector<FeatureIdSet> sets;
    ref_ptr<const PropertyStore> store;  // null when no set has a table and there are no property textures/attributes
    std::vector<int> propertyTextures;   // into store->propertyTextures
    std::vector<PropertyAttributeValues> propertyAttributes;

    // Set `set`'s feature id of vertex (or instance) `i`, or of the texel at `uv` for a texture set; -1 for the null
    // feature id, an index past the ids, or a texture set asked by index.
    int64_t idAt(size_t set, size_t i) const;
    int64_t idAtUv(size_t set, const vec2& uv) const;
    size_t bytes() const;
};

// The texel of `texture` nearest to `uv` (wrapped: glTF's default REPEAT), its channels' bytes in order.
std::vector<uint8_t> texelChannels(const Texture& texture, const vec2& uv, const std::vector<uint8_t>& channels);

}  // namespace sg
