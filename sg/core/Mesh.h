// Mesh: shared geometry (triangles, lines or points: positions, normals, optional UVs and colours, 16- or 32-bit
// indices).
#pragma once
#include "sg/core/Assert.h"
#include "sg/core/Features.h"
#include "sg/core/Math.h"
#include "sg/core/Ref.h"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace sg {

// Where a mesh was read from, for a pick to say: the file or URL, and the glTF mesh and primitive (-1: not glTF).
struct MeshSource {
    std::string file;
    int gltfMesh = -1, gltfPrimitive = -1;
};

// What a mesh draws: triangles (three indices a face), line segments (two indices each) or points (one a position,
// in order: points have no indices). glTF's strips, loops and fans become lists when read.
enum class Primitive : uint8_t { Triangles, Lines, Points };

// A morph target (glTF's mesh.primitives[].targets[]): displacements added to the base arrays, times the target's
// weight. Each array is empty or has one element per position.
struct MorphTarget {
    std::vector<vec3> positions, normals, tangents;
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

    // Points: one at each position, drawn in order; normals and colours empty or one per position (throws
    // std::invalid_argument otherwise, as set()). Non-finite positions are kept, as set() keeps them.
    void setPoints(std::vector<vec3> positions, std::vector<vec4> colors = {}, std::vector<vec3> normals = {});
    // Line segments: indices in pairs (throws std::invalid_argument for an odd count or an index out of range).
    void setLines(std::vector<vec3> positions, std::vector<uint32_t> indices, std::vector<vec4> colors = {});
    Primitive primitive() const { return primitive_; }
    // Per-vertex intensity as a scanner returns it (LAS: 0..65535), empty or one per position (throws
    // std::invalid_argument otherwise). Call after set*() (which clear it).
    void setIntensities(std::vector<uint16_t> intensities);
    const std::vector<uint16_t>& intensities() const { return intensities_; }
    // The distance between neighbouring points, in the mesh's units (a point tile's geometric error): what sizes
    // attenuated points on screen. 0: unknown. Kept by set*().
    void setPointSpacing(float spacing) { pointSpacing_ = spacing > 0.0f && std::isfinite(spacing) ? spacing : 0.0f; }
    float pointSpacing() const { return pointSpacing_; }
    // A triangle mesh's outline (glTF CESIUM_primitive_outline): edges in pairs of vertex indices, drawn as lines over
    // its faces. Throws std::invalid_argument for an odd count, an index out of range or a mesh that is not triangles.
    // Call after set() (which clears it).
    void setOutline(std::vector<uint32_t> edges);
    const std::vector<uint32_t>& outline() const { return outline_; }

    // Skinning (glTF JOINTS_n/WEIGHTS_n): `influences` (4 or 8) joint indices and weights a vertex, the vertex's
    // first four then its next four. A vertex goes where the weighted sum of its joints' matrices puts it
    // (Geometry::setSkin). Throws std::invalid_argument when the sizes are not influences x positions, `influences`
    // is not 4 or 8, a weight is negative or not finite, or the mesh is not triangles, lines or points with positions.
    // Weights that do not sum to one are normalised (`normalised` counts the vertices that were, for a warning);
    // all-zero weights become joint 0 with weight 1. Call after set*() (which clear them).
    void setSkinWeights(std::vector<uint16_t> joints, std::vector<float> weights, int influences,
                        size_t* normalised = nullptr);
    int influences() const { return influences_; }  // 0: not skinned
    const std::vector<uint16_t>& joints() const { return joints_; }
    const std::vector<float>& weights() const { return weights_; }
    // The largest joint index a weight above zero uses (0 when not skinned): a skin must have more joints.
    uint32_t maxJoint() const { return maxJoint_; }
    // Per joint, the bound of the vertices it moves (weight above zero): the cull's bound of any pose is the union of
    // these boxes through the joints' matrices, since a skinned vertex is a weighted mean of its joints' images of
    // it (sg/scene/Posing.h; a morphed pose uses its morphed mesh's boxes). Worked out on first use and kept; any
    // thread may call it.
    const std::vector<Box>& jointBoxes() const;

    // Morph targets (each array of each target empty or one element per position; throws std::invalid_argument
    // otherwise, naming the target). Call after set*() (which clear them).
    void setMorphTargets(std::vector<MorphTarget> targets);
    const std::vector<MorphTarget>& morphTargets() const { return targets_; }
    // glTF mesh.weights: the weights a Geometry starts with (empty: zeros).
    std::vector<float> defaultWeights;

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
    uint32_t triangleCount() const { return primitive_ == Primitive::Triangles ? indexCount() / 3 : 0; }
    uint32_t lineCount() const { return primitive_ == Primitive::Lines ? indexCount() / 2 : 0; }
    uint32_t pointCount() const { return primitive_ == Primitive::Points ? uint32_t(positions_.size()) : 0; }
    // Triangles, segments or points: what it draws (0: nothing).
    uint32_t primitiveCount() const { return triangleCount() + lineCount() + pointCount(); }
    // The bytes of its arrays (what a pager's memory budget and sgview --info count).
    size_t bytes() const {
        return positions_.size() * sizeof(vec3) + normals_.size() * sizeof(vec3) + uvs_.size() * sizeof(vec2) +
               colors_.size() * sizeof(vec4) + tangents_.size() * sizeof(vec4) + uvs1_.size() * sizeof(vec2) +
               indices16_.size() * sizeof(uint16_t) + indices32_.size() * sizeof(uint32_t) +
               intensities_.size() * sizeof(uint16_t) + outline_.size() * sizeof(uint32_t) +
               joints_.size() * sizeof(uint16_t) + weights_.size() * sizeof(float) + morphBytes() +
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
    size_t morphBytes() const;
    void store(const char* what, Primitive primitive, std::vector<vec3> positions, std::vector<vec3> normals,
               std::vector<uint32_t> indices, std::vector<vec2> uvs, std::vector<vec4> colors);

    std::vector<vec3> positions_, normals_;
    std::vector<vec2> uvs_;
    std::vector<vec4> colors_, tangents_;
    std::vector<vec2> uvs1_;
    std::vector<uint16_t> indices16_;
    std::vector<uint32_t> indices32_;
    std::vector<uint16_t> intensities_;
    std::vector<uint32_t> outline_;
    std::vector<uint16_t> joints_;
    std::vector<float> weights_;
    std::vector<MorphTarget> targets_;
    mutable std::vector<Box> jointBoxes_;  // jointBoxes(): worked out under the mutex, then kept
    mutable std::atomic<bool> jointBoxesDone_{false};
    mutable std::mutex jointBoxesMutex_;
    uint32_t maxJoint_ = 0;
    int influences_ = 0;
    Primitive primitive_ = Primitive::Triangles;
    float pointSpacing_ = 0.0f;
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
