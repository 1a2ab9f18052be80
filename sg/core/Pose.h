// Pose: what the update worked out for a skinned or morphed Geometry, for the cull and the draw of that frame. Made
// new for each update that changes it and never changed after: a frame in flight keeps its own (the draw list's
// packet holds a reference), while the application moves the joints for the next one.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"
#include "sg/core/Ref.h"

#include <vector>

namespace sg {

struct Pose : Referenced {
    // The morphed mesh (the Geometry's mesh with its weights applied, no targets), or null: the Geometry's own mesh.
    // The draw takes its vertices; its topology is the Geometry mesh's.
    ref_ptr<const Mesh> mesh;
    // Skinned: each joint's world matrix times its inverse bind matrix, less `anchor` (a world point near the
    // skeleton: the first joint's world translation), in float. The draw's item matrix is then the translation
    // from the eye to `anchor`, so that a figure far from the origin keeps float precision. Empty: not skinned
    // (the item's own matrix places `mesh`).
    dvec3 anchor{0.0};
    std::vector<glm::mat4x3> joints;
    // The world box of every vertex in this pose (skinned: the union of the mesh's jointBoxes() through the joints'
    // matrices; morphed only: the morphed mesh's box, in the Geometry's frame, not world).
    Box box;
    // What the morphed mesh was made of (makePose() reuses it while they hold): the weights, the base mesh's id and
    // version.
    std::vector<float> weights;
    uint32_t baseMesh = 0;
    uint64_t baseVersion = 0;
    bool skinned() const { return !joints.empty(); }
    const Mesh& drawn(const Mesh& own) const { return mesh ? *mesh : own; }
};

}  // namespace sg
