// VertexLightBaker: the view-independent part of lighting (how much of the sun and of the sky reach each
// vertex: soft shadows, ambient occlusion) computed by casting segments through a Scene, stored in the
// vertex colours, and cached on disk.
//
// Only visibility is baked; n.l, the light's colours and the highlight are the renderer's, per fragment,
// so that a sun can be dimmed or recoloured without a bake and highlights follow the eye. The vertex
// colours carry it (rgb the albedo times the occlusion, alpha the sun's visibility; Material::bakedLight
// tells the renderer) because they already travel with every mesh, its LOD levels and the GPU upload:
// no new array for Mesh. The price: five values in four channels, the occlusion also dims the sun's
// diffuse light, which only matters where a sunlit surface has a tall neighbour within aoDistance.
#pragma once
#include "sg/core/Mesh.h"
#include "sg/intersect/Intersect.h"
#include "sg/scene/Scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sg {

// A mesh placed once in the world: its vertices are lit where `world` puts them.
struct BakeTarget {
    ref_ptr<Mesh> mesh;
    dmat4 world{1.0};
};

struct VertexLightParams {
    dvec3 sunDirection = dvec3(0.0, 0.0, 1.0);  // toward the sun (need not be unit)
    double sunAngularRadius = 0.02;             // radians: the width of the penumbra
    int sunSamples = 16;                        // jittered rays toward the sun's disc per vertex
    int aoSamples = 32;                         // cosine-weighted hemisphere rays per vertex
    double aoDistance = 8.0;                    // an occluder further than this does not darken
    double sunDistance = 2000.0;                // sun rays stop here (beyond the scene)
    double offset = 0.05;                       // ray origins lifted along the normal (no self-hits)
    // Each vertex samples the light this share of the way toward the mean centroid of its triangles, at
    // most insetMax (mesh units) from it: the corner of a large face is not what the whole face sees. Where
    // that point lies under the vertex's own triangles (a convex bend) it is lifted onto them.
    double insetFraction = 0.3;
    double insetMax = 1.5;
    QueryOptions query;  // what the rays see (mask, LOD choice)
    int threads = 2;
};

// Per vertex of one target, both in [0, 1].
struct VertexLight {
    std::vector<float> sun;  // share of the sun rays that escape; 0 where the normal faces away from the sun
    std::vector<float> ao;   // share of the hemisphere rays that escape within aoDistance
};

class VertexLightBaker {
public:
    // Bumped whenever what a bake produces changes: older cache files are then ignored.
    static constexpr uint32_t kVersion = 3;

    // `scene` must be updated and hold what casts shadows. Deterministic: the jitter depends only on the
    // vertex and sample index. Throws std::invalid_argument naming the function for a null mesh, a zero or
    // non-finite sun direction, negative counts or distances.
    static std::vector<VertexLight> compute(const Scene& scene, const std::vector<BakeTarget>& targets,
                                            const VertexLightParams& params);
    // The colours a bakedLight material draws: rgb = albedo * ao, alpha = sun, the albedo being the mesh's
    // colours (white when it has none). Throws std::invalid_argument when the light's sizes are not the
    // mesh's vertex count.
    static std::vector<vec4> shade(const Mesh& mesh, const VertexLight& light);
    // Replaces the mesh's colours, keeping its other arrays.
    static void setColors(Mesh& mesh, std::vector<vec4> colors);

    // Bakes every target and sets its colours, reading them from `dir` when a file there matches (key,
    // kVersion, the parameters, the targets' vertex counts and albedo); otherwise computes them and writes
    // the file. A corrupt or mismatched file is recomputed and overwritten. Returns true when the cache was
    // used. An empty `dir` disables the cache; an unwritable one only costs the next start a bake.
    static bool bakeCached(const Scene& scene, const std::vector<BakeTarget>& targets, const VertexLightParams& params,
                           uint64_t key, const std::string& dir);
    // The file bakeCached() reads and writes for these inputs.
    static std::string cachePath(const std::vector<BakeTarget>& targets, const VertexLightParams& params, uint64_t key,
                                 const std::string& dir);
    // $XDG_CACHE_HOME/sgkit, else $HOME/.cache/sgkit, else empty (no cache).
    static std::string defaultCacheDir();
};

}  // namespace sg
