#include "sgview/Pick.h"

#include "sg/intersect/PickSet.h"

#include <cstdio>

namespace sgview {

std::string pickReport(sg::IntersectTraversal& traversal, const sg::Scene& scene, const sg::Camera& camera, double x,
                       double y) {
    char head[64];
    std::snprintf(head, sizeof head, "pick (%g, %g): ", x, y);
    // No objects registered: the path itself is the answer, down to the geometry that was hit.
    const sg::PickSet::Result r = sg::PickSet().pick(traversal, scene, camera, x, y);
    if (!r.hit) return head + std::string("nothing");
    const sg::Hit& h = r.nearest;
    char tail[160];
    std::snprintf(tail, sizeof tail, ", triangle %u, distance %.3f, at (%.3f, %.3f, %.3f)", unsigned(h.primitive),
                  h.distance, h.point.x, h.point.y, h.point.z);
    return head + sg::pathString(h.path) + tail;
}

}  // namespace sgview
