// The only place sgview meets the glTF loader; compiled when the sgkit::loaders target exists.
#include "sgview/LoadScene.h"

#include "loaders/Gltf.h"
#include "nodes/Transform.h"

namespace sgview {

LoadedScene loadSceneFile(const std::string& path) {
    sg::GltfScene g = sg::loadGltf(path);
    LoadedScene s;
    s.root = g.root;
    s.warnings = std::move(g.warnings);
    s.up = sg::dvec3(0.0, 1.0, 0.0);  // glTF's +Y up
    s.title = path;
    return s;
}

void saveSceneFile(const LoadedScene& scene, const std::string& path) {
    sg::ref_ptr<sg::Node> root = scene.root;
    if (scene.up == sg::dvec3(0.0, 0.0, 1.0)) {  // +Z up to glTF's +Y up: a quarter turn about X
        auto t = sg::make<sg::Transform>(glm::rotate(sg::dmat4(1.0), -glm::half_pi<double>(), sg::dvec3(1, 0, 0)));
        t->addChild(root);
        root = t;
    }
    sg::saveGltf(*root, path);
}

}  // namespace sgview
