// Mesh: shared triangle data (positions, normals, optional UVs and colours, 16- or 32-bit indices).
#pragma once
#include "sg/core/Assert.h"
#include "sg/core/Features.h"
#include "sg/core/Math.h"
#include "sg/core/Ref.h"

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace sg {

// Where a mesh was read from, for a pick to say: the file or URL, and the glTF mesh and primitive (-1: not glTF).
struct MeshSource {
    std::string file;
    int gltfMesh = -1, gltfPrimitive = -1;
};

class Mesh : public Referenced {
public:
    Mesh();
    // Throws std::invalid_argument when an index is out of range or the sizes disagree; the message
    // names the array and the first bad element. Non-finite positions are kept (the bound is then
    // invalid: the geometry is always drawn and counted).
    void set(std::vector<vec3> positions, std::vector<vec3> normals, std::vector<uint32_t> indices,
             std::vector<vec2> uvs = {}, std::vector<vec4> colors = {});

    // The attributes physical materials may read besides those of set(): tangents (xyz, and w = +-1 the
    // handedness of the bitangent, glTF's TANGENT) for normal maps and a second UV set. Each is empty or has
    // an element per position; throws std::invalid_argument otherwise. Call after set() (which clears them).
    void setSurface(std::vector<vec4> tangents, std::vector<vec2> uvs1);

    // What its features are (feature ID sets, property attributes: sg/core/Features.h). Throws
    // std::invalid_argument when an attribute set or a property attribute has not one value per vertex, or a texture
    // set has no texture. Call after set() (which clears them).
    void setFeatures(ref_ptr<const MeshFeatures> features);
    const MeshFeatures* features() const { return features_.get(); }
    void setSource(MeshSource source) { source_ = std::move(source); }
    const MeshSource& source() const { return source_; }

    const std::vector<vec3>& positions() const { return positions_; }
    const std::vector<vec3>& normals() const { return normals_; }
    const std::vector<vec2>& uvs() const { return uvs_; }
    const std::vector<vec4>& colors() const { return colors_; }
    const std::vector<vec4>& tangents() const { return tangents_; }
    const std::vector<vec2>& uvs1() const { return uvs1_; }
    // Exactly one of these is filled: 16-bit when every index fits.
    const std::vector<uint16_t>& indices16() const { return indices16_; }
    const std::vector<uint32_t>& indices32() const { return indices32_; }
    uint32_t indexCount() const { return uint32_t(indices16_.empty() ? indices32_.size() : indices16_.size()); }
    uint32_t index(size_t i) const {
        SG_ASSERT(i < indexCount(), "Mesh::index(): index past the index array");
        return indices16_.empty() ? indices32_[i] : indices16_[i];
    }
    uint32_t triangleCount() const { return indexCount() / 3; }
    // The bytes of its arrays (what a pager's memory budget and sgview --info count).
    size_t bytes() const {
        return positions_.size() * sizeof(vec3) + normals_.size() * sizeof(vec3) + uvs_.size() * sizeof(vec2) +
               colors_.size() * sizeof(vec4) + tangents_.size() * sizeof(vec4) + uvs1_.size() * sizeof(vec2) +
               indices16_.size() * sizeof(uint16_t) + indices32_.size() * sizeof(uint32_t) +
               (features_ ? features_->bytes() : 0);
    }

    // Local bound; `validBound()` is false when a position is NaN or infinite.
    const Box& box() const { return box_; }
    bool validBound() const { return valid_; }
    // Whether its triangles bound solids, wound counter-clockwise seen from outside: with positions welded where
    // equal, each edge is run along once each way and each connected part encloses a positive volume. From an eye
    // outside such a mesh's bound only front faces can show, so the renderer skips its back faces when the
    // material is opaque (Renderer::setBackFaceCulling). Worked out on the first call after set() (welding the
    // positions and pairing the edges: what it costs is in docs/benchmarks.md), then kept; any thread may call it, and
    // a program that loads meshes off its frame (a pager's load function) calls it there so that the first draw does
    // not wait.
    bool closed() const;
    uint32_t id() const { return id_; }
    // Counts calls to set(): caches built from the arrays (MeshBvh) compare it to see that they are stale.
    uint64_t version() const { return version_; }

private:
    std::vector<vec3> positions_, normals_;
    std::vector<vec2> uvs_;
    std::vector<vec4> colors_, tangents_;
    std::vector<vec2> uvs1_;
    std::vector<uint16_t> indices16_;
    std::vector<uint32_t> indices32_;
    ref_ptr<const MeshFeatures> features_;
    MeshSource source_;
    Box box_;
    bool valid_ = true;
    mutable std::atomic<int8_t> closed_{-1};  // closed(): -1 until worked out
    uint32_t id_;
    uint64_t version_ = 0;
};

// Tangents for a normal map over UV set `texCoord` (0 or 1), following MikkTSpace's rules where a vertex is not
// split: each triangle's tangent and bitangent from its UV gradients, summed at its corners weighted by the corner
// angle, then made orthogonal to the vertex normal, w the bitangent's side (+1 or -1). Vertices without a UV
// gradient (degenerate UVs) get any tangent orthogonal to the normal. Needs normals and that UV set.
std::vector<vec4> generateTangents(const Mesh& mesh, int texCoord);

// Builders for the shapes the tests, benchmarks and demos use.
// Box [min,max] with each face split into `div` x `div` quads, outward normals.
ref_ptr<Mesh> makeBoxMesh(const dvec3& min, const dvec3& max, int div = 1);

}  // namespace sg
