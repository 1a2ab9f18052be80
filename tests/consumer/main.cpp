// Builds a graph with the installed library, culls it and draws it through sg::Viewer (OSMesa): exits 0 when one
// of two boxes is drawn, in the middle of the picture, and an LOD, a glTF round trip and a resource read work.
#include <loaders/gltf/Gltf.h>
#include <loaders/net/Resource.h>
#include <nodes/Geometry.h>
#include <nodes/Transform.h>
#include <sg/build/LodGenerator.h>
#include <sg/cull/CullTraversal.h>
#include <sg/gl/OsmesaContext.h>
#include <sg/viewer/Viewer.h>

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
    std::printf("consumer: %zu of 2 boxes culled in\n", list.items.size());
    // The frame loop: the same view drawn; the box fills the middle of the picture, the sky its corner.
    OsmesaContext context(64, 64);
    Viewer viewer(scene);
    View& view = viewer.addView(cam);
    view.camera.setViewport(64, 64);
    viewer.frame();
    const Image picture = viewer.renderer().readColor();
    const auto rgb = [&](int x, int y) {
        const uint8_t* p = &picture.rgba[(size_t(y) * 64 + size_t(x)) * 4];
        return (uint32_t(p[0]) << 16) | (uint32_t(p[1]) << 8) | p[2];
    };
    const bool drawn = view.renderStats().instances == 1 && rgb(32, 32) != rgb(0, 0);
    std::printf("consumer: viewer drew %llu geometries, middle %06x, corner %06x\n",
                (unsigned long long)view.renderStats().instances, rgb(32, 32), rgb(0, 0));
    // Generated levels: links meshoptimizer through the package's dependencies.
    const auto lod = makeLod(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>(), {0.5f});
    std::printf("consumer: LOD with %zu levels\n", lod->numChildren());
    // glTF through the package: sgkit::loaders and its tinygltf dependency.
    const std::string file = (std::filesystem::temp_directory_path() / "sgkit_consumer.glb").string();
    saveGltf(*root, file);
    const GltfScene loaded = loadGltf(file);
    std::printf("consumer: glTF round trip with %zu of 2 nodes\n", loaded.root->numChildren());
    // The same file as a resource, by file:// URL: links libcurl through the package's dependencies.
    const size_t bytes = readResource("file://" + file).size();
    std::printf("consumer: read %zu bytes of %zu\n", bytes, size_t(std::filesystem::file_size(file)));
    const bool ok = list.items.size() == 1 && drawn && lod->numChildren() == 2 && loaded.root->numChildren() == 2 &&
                    bytes == std::filesystem::file_size(file);
    return ok ? 0 : 1;
}
