// Loading what sgview shows: glTF files (LoadScene.cpp, through loaders/gltf/Gltf.h) or a built-in scene.
#pragma once
#include "sg/core/Animation.h"
#include "sg/core/DirectionalLight.h"
#include "sg/core/Math.h"
#include "sg/core/Node.h"
#include "sg/paging/Pager.h"
#include "sg/scene/AnimationPlayer.h"
#include "sg/style/FeatureStyle.h"
#include "sgview/Options.h"

#include <functional>
#include <string>
#include <vector>

namespace sgview {

struct LoadedScene {
    sg::ref_ptr<sg::Node> root;
    std::vector<std::string> warnings;  // what the loader skipped or converted
    sg::dvec3 up{0.0, 0.0, 1.0};        // the scene's up axis: +Z for the built-in scenes, +Y for glTF
    std::string title;
    std::vector<sg::PunctualLight> lights = {};  // a glTF file's KHR_lights_punctual lights (the renderer's first ones)
    // A tileset's: the pager's load function for its tiles, and a line on its tiles for --info (tiles read,
    // contents loaded and failed) with a line per failed content (its tile's JSON path, URI and reason); empty for
    // glTF files and built-in scenes.
    sg::PageLoadFunction pageLoad = {};
    std::function<std::string()> tilesReport = {};
    sg::FeatureStyle::Rule styleRule = {};                    // --style: the features' colours and visibility
    std::vector<sg::ref_ptr<sg::Animation>> animations = {};  // a glTF file's, or the built-in figures' walks
};

// The animations --animation names (all, a name or an index; empty: the first) into the viewer's player, playing;
// paused at --time with --headless (0 when not given), else started there. Returns a line saying what plays (empty
// when the scene has none). Throws UsageError naming an animation the scene does not have, with those it has.
std::string startAnimations(sg::AnimationPlayer& player, const LoadedScene& scene, const Options& o);

// One glTF file or 3D Tiles tileset (LoadScene.cpp; a path or, for a tileset, a URL), every tile loaded with
// o.refineAll; a tileset's tiles make their occluders as they are read with o.autoOccluders
// (sg::TilesetOptions::generateOccluders), and are read with o's headers, authorities and cache. Throws
// sg::LoadError naming the file, the JSON path and the reason.
LoadedScene loadSceneFile(const std::string& path, const Options& o);

// A 3D Tiles style file (--style) as a rule for the view's FeatureStyle: evaluated for each property table as it is
// first drawn. Throws sg::LoadError for a file that cannot be read or an expression that does not parse (its JSON
// path, the expression and the position); an expression that cannot read a table's properties (a property of the
// wrong type) is printed on stderr once, naming the expression and the position, and leaves that table as it is.
sg::FeatureStyle::Rule loadStyleFile(const std::string& path);

// Writes the scene as glTF (.glb or .gltf), turned to glTF's +Y up when its up axis is +Z.
void saveSceneFile(const LoadedScene& scene, const std::string& path);

// The files (under one Group, warnings prefixed with the file name) or the built-in scene of `o`.
// Throws UsageError for a file that does not exist or cannot be loaded, naming it.
LoadedScene loadScene(const Options& o);

}  // namespace sgview
