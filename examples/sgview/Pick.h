// Picking in sgview: what lies under a pixel of a view, with the features it struck and their properties (a click
// in the window, or --pick X,Y headless), as text or as one JSON object.
#pragma once
#include "sg/core/Camera.h"
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/scene/Scene.h"

#include <string>

namespace sgview {

// Text: "pick (x, y): Group / Group 'tile 3' / Transform / LOD / Geometry, triangle 17, distance 42.3, at (…)"
// or "pick (x, y): nothing", then a line per feature ID set ("  feature set 0 'building': id 12, class building:
// height 54.5, name Main hall") and per property texture or attribute. x, y in framebuffer pixels, y down.
// JSON (`json`): one line, {"pixel": [x, y], "hit": false} or {"pixel", "hit": true, "node_path", "source",
// "gltf_mesh", "gltf_primitive", "triangle", "distance", "point", "features", "property_textures",
// "property_attributes"} (docs/guide.md).
// Hidden features of `style` (when given) are not picked.
struct Pick {
    double x = 0.0, y = 0.0;
    bool hit = false;
    sg::Hit nearest;
    sg::HitFeatures features;
};
Pick pickAt(sg::IntersectTraversal& traversal, const sg::Scene& scene, const sg::Camera& camera, double x, double y,
            sg::FeatureStyle* style = nullptr);
std::string pickReport(const Pick& pick, bool json = false);
std::string pickReport(sg::IntersectTraversal& traversal, const sg::Scene& scene, const sg::Camera& camera, double x,
                       double y, bool json = false, sg::FeatureStyle* style = nullptr);
// The window's panel: the first feature with properties, a line each ("building 12", "height 54.5", ...); empty
// when the pick has none.
std::string featurePanel(const Pick& pick);

// The JSON object of one pick's features (the "features" array and the property arrays), for other programs.
std::string featuresJson(const sg::HitFeatures& f);

}  // namespace sgview
