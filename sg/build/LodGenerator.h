// Levels of detail for a mesh, made by meshoptimizer's simplifier, and an LOD node built from them in one call.
#pragma once
#include "nodes/LOD.h"
#include "sg/build/LevelReshade.h"
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace sg {

struct LodLevel {
    ref_ptr<Mesh> mesh;      // level 0 is the input mesh itself; the others are new meshes
    float error = 0.0f;      // geometric error against level 0, absolute, in the mesh's units
    uint32_t triangles = 0;  // triangles reached (the simplifier may stop above the target)
    LevelColorShare colors;  // with LevelShading::reshade, how its colours derive from level 0's
};

// How generateLevels shades the coarse levels.
struct LevelShading {
    // Off: each level keeps its vertices' attributes as the simplifier picked them (smooth models). On: every
    // coarse level is rebuilt by LevelReshader (faceted models, whose kept vertices carry other faces'
    // normals, texture coordinates and colours), and `colors` tells how to redo its colours from level 0's.
    bool reshade = false;
    ReshadeParams params;
};

// Level 0 is `mesh` (error 0); then one level per ratio, simplified from `mesh` to about ratio * its
// triangles. Ratios must lie in (0, 1) and decrease. A level's error is what meshoptimizer reports
// (the largest deviation of the simplified surface, by its quadric measure), raised where needed to the
// previous level's so that errors never decrease along the levels: a level never claims to be more
// accurate than a finer one, and distances derived from the errors are in order.
//
// The simplifier stops short of a ratio rather than deviate more than `maxError` (absolute, the mesh's
// units; by default no limit). Where it cannot get near the target because of the mesh's topology (a
// tiny mesh, seams everywhere), a topology-ignoring ("sloppy") simplification is used when it gets closer;
// `triangles` tells what was reached. A level that cannot get below the one before repeats it (same mesh,
// error and count), so counts never grow along the levels.
//
// Each level keeps only the vertices it uses, with their normals, UVs and colours unchanged. Throws
// std::invalid_argument, naming the function and the value, for a null mesh, a mesh without triangles or
// with a non-finite position, a ratio outside (0, 1), NaN or not below the previous one, and a negative
// or NaN maxError.
//
// With shading.reshade, each new coarse level is reshaded from level 0 (LevelReshader::reshade; its collapsed
// triangles dropped, `triangles` counts what is left) and level 0 and the levels that repeat it get the
// identity colour share.
std::vector<LodLevel> generateLevels(const ref_ptr<Mesh>& mesh, const std::vector<float>& ratios,
                                     float maxError = std::numeric_limits<float>::infinity(),
                                     const LevelShading& shading = {});

// Pixels per radian of a 1080-pixel-tall view with a 60 degree vertical field of view (540 / tan 30°).
// For another view pass Camera::pixelsPerUnit(), which is the same quantity.
constexpr double kDefaultPixelsPerRadian = 935.3074;

// An LOD in Distance mode whose child i is a Geometry of level i of generateLevels(mesh, ratios) with
// `material`, and whose error(i) is that level's error. Each level is shown only from the distance where
// its error projects to at most `pixelError` pixels: level i >= 1 from d_i = error_i * pixelsPerRadian /
// pixelError, to the next level's d; level 0 from 0; the last level to the largest float. A level whose
// error equals the next one's gets an empty range (the coarser level looks as good and costs less).
// The cull measures the distance from the eye to the LOD's centre (by default its bound's centre) in world
// units, while errors are in the mesh's units: below a transform that scales by s, scale the ranges by s.
// Near a large mesh its surface is nearer than the centre, and the error there projects a little larger.
// Throws std::invalid_argument as generateLevels does, and for a pixelError or pixelsPerRadian that is
// not positive and finite.
ref_ptr<LOD> makeLod(ref_ptr<Mesh> mesh, ref_ptr<Material> material, const std::vector<float>& ratios,
                     double pixelError = 1.0, double pixelsPerRadian = kDefaultPixelsPerRadian);
// The same from levels already generated (e.g. reshaded ones, whose colour shares the caller keeps). Throws
// std::invalid_argument naming the function for no levels, a null mesh or errors that decrease.
ref_ptr<LOD> makeLod(const std::vector<LodLevel>& levels, ref_ptr<Material> material, double pixelError = 1.0,
                     double pixelsPerRadian = kDefaultPixelsPerRadian);

}  // namespace sg
