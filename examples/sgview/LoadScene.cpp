// The only place sgview meets the glTF loader; compiled when the sgkit::loaders target exists.
#include "sgview/LoadScene.h"

#include "loaders/Gltf.h"

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

}  // namespace sgview
