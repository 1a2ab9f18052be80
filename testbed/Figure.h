// The test figure: a walking skinned figure of 20 joints and about 3,000 triangles, for the motion tests, the
// crowd benchmark (1,000 of them in the city) and sgview's demonstration. Its skeleton is a tree of Transforms
// (pelvis, spine, chest, neck, head; clavicles, upper arms, forearms, hands; thighs, shins, feet), its skin one mesh of
// tubes along the bones, blended across each joint, and its walk a one-second loop of rotations (LINEAR or
// CUBICSPLINE) and a pelvis bob (STEP or LINEAR).
#pragma once
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/core/Animation.h"

#include <cstdint>
#include <vector>

namespace scenes {

struct FigureOptions {
    int influences = 4;    // 4, or 8 (each vertex then also weighs its grandparent joint a little)
    bool cubic = false;    // the walk's rotations in CUBICSPLINE (with tangents), else LINEAR
    bool stepBob = false;  // the pelvis bob in STEP, else LINEAR
    int sides = 12;        // around each tube
    int rings = 5;         // along each bone
    double height = 1.8;   // metres, standing
    sg::vec4 color{0.85f, 0.55f, 0.35f, 1.0f};
};

struct Figure {
    sg::ref_ptr<sg::Group> root;          // holds the skeleton and the skinned Geometry beside it
    sg::ref_ptr<sg::Transform> skeleton;  // the pelvis joint (place the figure with its parent, `root`'s Transform)
    sg::ref_ptr<sg::Geometry> body;       // skinned by `skin`
    sg::ref_ptr<sg::Skin> skin;           // 20 joints
    sg::ref_ptr<sg::Animation> walk;      // one second, looping
};

constexpr int kFigureJoints = 20;

// A figure standing at the origin, +Y up, facing +Z. Deterministic.
Figure makeFigure(const FigureOptions& opt = {});

// `count` figures in rows of `columns`, `spacing` apart, the first at `first`, each with its own copy of the skeleton
// and walk (phases spread over the step), their skinned meshes sharing one Mesh. Rows run along +Z (+Y with zUp, where
// each figure stands on the z = first.z plane, up +Z, as the city is built). The walks, one a figure, are returned in
// `walks`.
sg::ref_ptr<sg::Group> makeCrowd(int count, const sg::dvec3& first, int columns, double spacing,
                                 std::vector<sg::ref_ptr<sg::Animation>>& walks, const FigureOptions& opt = {},
                                 bool zUp = false);

}  // namespace scenes
