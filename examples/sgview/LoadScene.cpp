// The only place sgview meets the glTF loader; compiled when the sgkit::loaders target exists.
#include "sgview/LoadScene.h"

#include "loaders/gltf/Gltf.h"
#include "loaders/tiles/Tileset.h"
#include "nodes/Transform.h"
#include "sg/gl/Renderer.h"

#include <memory>

namespace sgview {

namespace {

LoadedScene loadTilesetFile(const std::string& path, bool refineAll, bool autoOccluders) {
    sg::TilesetOptions to;
    to.generateOccluders = autoOccluders;  // each tile's, as it is read
    auto ts = std::make_shared<sg::Tileset>(sg::loadTileset(path, to));
    LoadedScene s;
    s.root = ts->root();
    s.pageLoad = ts->loadFunction();
    if (refineAll) sg::refineAll(*s.root, s.pageLoad);
    s.warnings = ts->warnings();
    s.up = sg::dvec3(0.0, 0.0, 1.0);  // 3D Tiles' +Z up
    s.title = path;
    s.tilesReport = [ts] {
        const sg::TilesetCounts c = ts->counts();
        return "tiles " + std::to_string(c.tiles) + " (" + std::to_string(c.externalTilesets) +
               " external tilesets), contents loaded " + std::to_string(c.contents) + ", point clouds skipped " +
               std::to_string(c.skippedPoints);
    };
    return s;
}

}  // namespace

LoadedScene loadSceneFile(const std::string& path, bool refineAll, bool autoOccluders) {
    if (sg::isUrl(path) || sg::isTilesetFile(path)) return loadTilesetFile(path, refineAll, autoOccluders);
    if (refineAll) throw sg::LoadError(path, "", "--refine-all: not a 3D Tiles tileset");
    sg::GltfScene g = sg::loadGltf(path);
    LoadedScene s;
    s.root = g.root;
    s.warnings = std::move(g.warnings);
    s.up = sg::dvec3(0.0, 1.0, 0.0);  // glTF's +Y up
    s.lights = std::move(g.lights);
    if (s.lights.size() > sg::Renderer::kMaxLights) {
        s.warnings.push_back("KHR_lights_punctual: " + std::to_string(s.lights.size()) + " lights, the first " +
                             std::to_string(sg::Renderer::kMaxLights) + " are shown");
        s.lights.resize(sg::Renderer::kMaxLights);
    }
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
