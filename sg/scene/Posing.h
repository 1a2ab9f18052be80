// Posing: what a skinned or morphed Geometry looks like now. The update makes a Pose for each such Geometry whose
// joints or weights changed (sg/core/Pose.h); picks and collisions pose the Geometry the same way from the nodes,
// and the tests compare the renderer's skinning with skinMesh().
#pragma once
#include "nodes/Geometry.h"
#include "sg/core/Pose.h"

#include <vector>

namespace sg {

// A node's world matrix through its first parents (Transforms' matrices; other kinds place nothing).
dmat4 worldMatrix(const Node& n);
// Each joint's world matrix times its inverse bind matrix, in double (parents shared between joints are multiplied
// once).
std::vector<dmat4> skinMatrices(const Skin& skin);
// The mesh with these morph weights applied to its positions, normals (renormalised) and tangents (xyz, w kept),
// without targets; the rest of its arrays copied. Weights past the targets are 0. Null when every weight is 0.
ref_ptr<Mesh> morphMesh(const Mesh& mesh, const std::vector<float>& weights);
// The pose of `g` now: the morphed mesh if weighted, the skin's matrices less their anchor, the box (see Pose).
// `previous` (the last pose, or null) lends its morphed mesh when the weights and the mesh are those it was made
// of. Throws std::invalid_argument naming the Geometry when its mesh names a joint past its skin.
ref_ptr<const Pose> makePose(const Geometry& g, const Pose* previous = nullptr);
// The mesh as drawn in this pose, in world coordinates for a skinned pose (positions and normals skinned on the
// CPU, in double), in the Geometry's frame otherwise: what picks and collisions test and the skinning tests compare
// the renderer's pictures with. Topology as the Geometry's mesh.
ref_ptr<Mesh> skinMesh(const Mesh& mesh, const Pose& pose);

}  // namespace sg
