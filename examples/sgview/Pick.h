// Picking in sgview: what lies under a pixel of a view, as one line with its node path (a click in the
// window, or --pick X,Y headless).
#pragma once
#include "sg/core/Camera.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/scene/Scene.h"

#include <string>

namespace sgview {

// "pick (x, y): Group / Group 'tile 3' / Transform / LOD / Geometry, triangle 17, distance 42.3 m, at (…)"
// or "pick (x, y): nothing". x, y in framebuffer pixels, y down.
std::string pickReport(sg::IntersectTraversal& traversal, const sg::Scene& scene, const sg::Camera& camera, double x,
                       double y);

}  // namespace sgview
