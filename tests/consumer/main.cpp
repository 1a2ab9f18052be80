// Builds a graph with the installed library and culls it: exits 0 when one of two boxes is drawn.
#include <loaders/Gltf.h>
#include <nodes/Geometry.h>
#include <nodes/Transform.h>
#include <sg/cull/CullTraversal.h>
#include <sg/lod/LodGenerator.h>

#include <cstdio>
#include <filesystem>

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
    // glTF through the package: sgkit::loaders and its tinygltf dependency.
    const std::string file = (std::filesystem::temp_directory_path() / "sgkit_consumer.glb").string();
    saveGltf(*root, file);
    const GltfScene loaded = loadGltf(file);
    std::printf("consumer: glTF round trip with %zu of 2 nodes\n", loaded.root->numChildren());
    return list.items.size() == 1 && lod->numChildren() == 2 && loaded.root->numChildren() == 2 ? 0 : 1;
}
