// Builds a graph with the installed library and culls it: exits 0 when one of two boxes is drawn.
#include <nodes/Geometry.h>
#include <nodes/Transform.h>
#include <sg/CullTraversal.h>
#include <sg/LodGenerator.h>

#include <cstdio>

int main() {
    using namespace sg;
    auto root = make<Group>();
    for (double z : {-10.0, 10.0}) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, z)));
        t->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
        root->addChild(t);
    }
    Scene scene(root);
    scene.update();
    Camera cam;
    cam.setLookAt(dvec3(0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    DrawList list;
    CullStats stats;
    CullTraversal().cull(scene, cam, CullSettings{}, list, stats);
    std::printf("consumer: %zu of 2 boxes drawn\n", list.items.size());
    // Generated levels: links meshoptimizer through the package's dependencies.
    const auto lod = makeLod(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>(), {0.5f});
    std::printf("consumer: LOD with %zu levels\n", lod->numChildren());
    return list.items.size() == 1 && lod->numChildren() == 2 ? 0 : 1;
}
