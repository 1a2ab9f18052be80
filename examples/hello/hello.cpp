// hello: the smallest complete sgkit program: build a graph, run one frame of it through sg::Viewer (update,
// cull, draw), headless, and write the picture to a PNG.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/io/ImageIO.h"
#include "sg/viewer/Viewer.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) try {
    using namespace sg;
    const char* out = argc > 1 ? argv[1] : "hello.png";

    // Two boxes with their own materials; the second is an LOD whose coarse child shows beyond 20 m.
    auto root = make<Group>();
    auto left = make<Transform>(glm::translate(dmat4(1.0), dvec3(-1.2, 0.0, 0.0)));
    left->addChild(make<Geometry>(makeBoxMesh(dvec3(-0.8), dvec3(0.8)), make<Material>(vec4(0.9f, 0.3f, 0.2f, 1.0f))));
    auto right = make<Transform>(glm::rotate(glm::translate(dmat4(1.0), dvec3(1.2, 0.0, 0.0)), 0.6, dvec3(0, 1, 0)));
    auto lod = make<LOD>();
    auto blue = make<Material>(vec4(0.2f, 0.4f, 0.9f, 1.0f));
    lod->addChild(make<Geometry>(makeBoxMesh(dvec3(-0.7), dvec3(0.7), 8), blue), 0.0f, 20.0f);
    lod->addChild(make<Geometry>(makeBoxMesh(dvec3(-0.7), dvec3(0.7), 1), blue), 20.0f, 1e30f);
    right->addChild(lod);
    root->addChild(left);
    root->addChild(right);

    Scene scene(root);
    OsmesaContext context(640, 480);
    Viewer viewer(scene);  // the frame loop: app callbacks, update, cull, draw, stats
    View& view = viewer.addView();
    view.camera.setLookAt(dvec3(2.0, 3.0, 6.0), dvec3(0.0), dvec3(0.0, 1.0, 0.0));
    view.camera.setPerspective(45.0, 640.0 / 480.0, 0.1, 100.0);
    view.camera.setViewport(640, 480);
    viewer.frame();
    savePng(out, viewer.renderer().readColor());

    const RenderStats& s = view.renderStats();
    std::printf("%s: %llu geometries, %llu draw calls, %llu triangles, frame %.2f ms\n", out,
                (unsigned long long)s.instances, (unsigned long long)s.drawCalls, (unsigned long long)s.triangles,
                viewer.lastFrame().frameMs);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "hello: %s\n", e.what());
    return 1;
}
