// What the renderer draws of a scene from a camera (needs a current GL context): updated, culled with the default
// strategy, drawn and read back. `sort` false keeps emission order, so two copies of a graph draw in the same order
// whatever their pointers.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/gl/Renderer.h"
#include "sg/scene/Scene.h"

namespace testutil {

inline sg::Image drawScene(sg::Renderer& r, const sg::Scene& scene, const sg::Camera& cam, bool sort = false,
                           const sg::vec4& clear = sg::Renderer::kClearColor) {
    sg::DrawList list;
    sg::CullStats stats;
    sg::CullSettings settings;
    settings.sort = sort;
    sg::CullTraversal().cull(scene, cam, settings, list, stats);
    r.draw(list, cam, clear);
    return r.readColor();
}

inline sg::Image drawGraph(sg::Renderer& r, const sg::ref_ptr<sg::Node>& root, const sg::Camera& cam, bool sort = false,
                           const sg::vec4& clear = sg::Renderer::kClearColor) {
    sg::Scene scene(root);
    scene.update();
    return drawScene(r, scene, cam, sort, clear);
}

}  // namespace testutil
