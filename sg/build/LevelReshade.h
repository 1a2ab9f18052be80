// LevelReshade: a simplified level of a faceted model shaded like the detailed model it stands for (normals of its
// own faces, texture coordinates and colours sampled from the detailed surface under it).
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace sg {

// How a coarse level takes its colours from the detailed level: vertex v's colour is the sum, over k in
// [start[v], start[v + 1]), of weight[k] times the detailed level's colour of its vertex from[k]. Kept so that
// colours changed later (baked light) reach the coarse levels again through applyColorShare.
struct LevelColorShare {
    std::vector<uint32_t> start, from;
    std::vector<float> weight;
};

// The share of a level that is the detailed mesh itself: each vertex its own colour.
LevelColorShare identityColorShare(size_t vertices);

struct ReshadeParams {
    double sampleSpacing = 1.0;  // the detailed colours are sampled about this far apart over each coarse triangle
    double searchRadius = 2.0;   // the farthest a detailed surface is looked for from a coarse point
    vec2 fallbackUv{0.0f};       // texture coordinates of a coarse vertex with no detailed surface that near
};

// The detailed level of a model (kept by reference, with a BVH over it), reshading its coarse levels.
class LevelReshader {
public:
    explicit LevelReshader(const Mesh& fine, const ReshadeParams& params = {});
    ~LevelReshader();
    LevelReshader(const LevelReshader&) = delete;
    LevelReshader& operator=(const LevelReshader&) = delete;

    // A coarse level as the simplifier leaves a flat-shaded model: its triangles reuse whichever vertex each
    // cluster kept, with that vertex's normal and texture coordinates, which mostly belong to a face that looks
    // another way (sun and shade on the wrong walls, a texture scattered). Rebuilt with a vertex per position
    // and face orientation, its normal the faces' and its texture coordinates (when the detailed level has
    // them) and colours the detailed surface's there, facing within 45 degrees the same way; collapsed
    // triangles are dropped. Returns the colour share, applied when the detailed level has colours.
    LevelColorShare reshade(Mesh& coarse) const;

private:
    struct Surface;
    std::unique_ptr<Surface> surface_;
};

// Sets `coarse`'s colours from the detailed level's colours by `share`. Throws std::invalid_argument naming
// `fn` when the share was made for another mesh or reads a colour the detailed level does not have.
void applyColorShare(const LevelColorShare& share, const std::vector<vec4>& fineColors, Mesh& coarse,
                     const char* fn = "sg::applyColorShare()");

}  // namespace sg
