// The posed Geometries a query meets: each one's mesh as it stands (skinned or morphed on the CPU, Posing.h), kept
// with its hierarchies while the Geometry keeps that pose, so that repeated picks of a still figure build nothing.
#include "nodes/Geometry.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/scene/Posing.h"

namespace sg {

IntersectTraversal::Posed& IntersectTraversal::posed(const Geometry& g, const Pose& pose) {
    Posed& p = posed_[&g];
    // Poses are never changed once made, and each entry holds its pose: the same pointer is the same pose.
    if (p.pose.get() != &pose || !p.mesh) {
        p.geometry = &g;  // held, so that its address is not reused while the entry is kept
        p.pose = &pose;
        p.mesh = skinMesh(*g.mesh(), pose);
        p.triangles.reset();
        p.points.reset();
    }
    return p;
}

}  // namespace sg
