// The only place sgview meets the glTF loader; compiled when the sgkit::loaders target exists.
#include "sgview/LoadScene.h"

#include "loaders/gltf/Gltf.h"
#include "loaders/net/HttpCache.h"
#include "loaders/points/Scan.h"
#include "loaders/tiles/StyleJson.h"
#include "loaders/tiles/Tileset.h"
#include "nodes/Transform.h"
#include "sg/gl/Renderer.h"
#include "sg/style/StyleTable.h"

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <set>

namespace sgview {

namespace {

// The directory of the HTTP cache: --cache DIR, else $XDG_CACHE_HOME/sgkit, else ~/.cache/sgkit; "" when none of
// them is known.
std::string cacheDirectory(const Options& o) {
    if (!o.cacheDir.empty()) return o.cacheDir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && xdg[0] == '/') return std::string(xdg) + "/sgkit";
    if (const char* home = std::getenv("HOME"); home && home[0]) return std::string(home) + "/.cache/sgkit";
    return "";
}

// The disk cache of a tileset read over http(s), unless --no-cache; none (a warning said why) when it cannot be
// made: the tileset is read from the server.
std::shared_ptr<sg::HttpCache> openCache(const std::string& path, const Options& o,
                                         std::vector<std::string>& warnings) {
    if (o.noCache || !sg::isUrl(path)) return nullptr;
    const std::string dir = cacheDirectory(o);
    if (dir.empty()) {
        warnings.push_back("no HTTP cache: neither --cache DIR, XDG_CACHE_HOME nor HOME is set");
        return nullptr;
    }
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        warnings.push_back("no HTTP cache: cannot make " + dir + ": " + ec.message());
        return nullptr;
    }
    auto cache = std::make_shared<sg::HttpCache>(dir + "/http.sqlite");
    if (cache->enabled()) return cache;  // its warnings, the opening's and the reads', are taken after the loads
    for (const std::string& w : cache->warnings()) warnings.push_back(w);
    return nullptr;
}

LoadedScene loadTilesetFile(const std::string& path, const Options& o) {
    sg::TilesetOptions to;
    to.generateOccluders = o.autoOccluders;  // each tile's, as it is read
    to.resource.headers = o.headers;
    to.resource.caFile = o.caFile;
    std::vector<std::string> cacheWarnings;
    to.resource.cache = openCache(path, o, cacheWarnings);
    auto ts = std::make_shared<sg::Tileset>(sg::loadTileset(path, to));
    LoadedScene s;
    s.root = ts->root();
    s.pageLoad = ts->loadFunction();
    // A content that fails for a reason that may pass is read again at once, up to the tileset's attempts, past
    // which it is given up as a missing one: --refine-all then shows every tile that could be read.
    if (o.refineAll) sg::refineAll(*s.root, s.pageLoad, to.transientAttempts);
    s.warnings = std::move(cacheWarnings);
    if (to.resource.cache)
        for (const std::string& w : to.resource.cache->warnings()) s.warnings.push_back(w);
    for (const std::string& w : ts->warnings()) s.warnings.push_back(w);
    s.up = sg::dvec3(0.0, 0.0, 1.0);  // 3D Tiles' +Z up
    s.title = path;
    // A cache that failed a lookup or a store while tiles loaded says so with the tiles (a window's run, at exit).
    const size_t said = to.resource.cache ? to.resource.cache->warnings().size() : 0;
    s.tilesReport = [ts, cache = to.resource.cache, said] {
        const sg::TilesetCounts c = ts->counts();
        std::string report = "tiles " + std::to_string(c.tiles) + " (" + std::to_string(c.externalTilesets) +
                             " external tilesets), contents loaded " + std::to_string(c.contents) + ", points loaded " +
                             std::to_string(c.points) + ", failed " + std::to_string(c.failed);
        for (const sg::TileFailure& f : ts->failures())
            report += "\n  failed " + f.file + ": " + f.path + ": " + f.uri + ": " + f.reason +
                      (f.final ? "" : " (to be tried again)");
        if (cache && cache->warnings().size() > said)
            report += "\n  the HTTP cache: " + cache->warnings().back() + " (" +
                      std::to_string(cache->warnings().size()) + " warnings in all)";
        return report;
    };
    return s;
}

// A laser scan by its name (LAS; a LAZ is named so that openScan says how to convert it; PLY).
bool isScanFile(const std::string& path) {
    const size_t dot = path.rfind('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == "las" || ext == "laz" || ext == "ply";
}

}  // namespace

sg::FeatureStyle::Rule loadStyleFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw sg::LoadError(path, "", "cannot be read");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::string> warnings;
    auto style = std::make_shared<const sg::Style>(sg::parseStyleJson(path, text, &warnings));
    for (const std::string& w : warnings) std::fprintf(stderr, "sgview: %s: %s\n", path.c_str(), w.c_str());
    auto reported = std::make_shared<std::set<std::string>>();  // the rule runs under the style's lock
    return [style, reported, path](const sg::PropertyStore& store, int table, std::vector<uint8_t>& rgba) {
        try {
            rgba = sg::styleTable(*style, store, table).rgba;
        } catch (const std::exception& e) {
            if (reported->insert(e.what()).second)
                std::fprintf(stderr, "sgview: --style %s: %s (the table is drawn unstyled)\n", path.c_str(), e.what());
        }
    };
}

LoadedScene loadSceneFile(const std::string& path, const Options& o) {
    if (sg::isUrl(path) || sg::isTilesetFile(path)) return loadTilesetFile(path, o);
    if (o.refineAll) throw sg::LoadError(path, "", "--refine-all: not a 3D Tiles tileset");
    if (isScanFile(path)) {
        LoadedScene s;
        s.root = sg::loadScan(path);
        s.up = sg::dvec3(0.0, 0.0, 1.0);  // surveys' +Z up
        s.title = path;
        return s;
    }
    sg::GltfScene g = sg::loadGltf(path);
    LoadedScene s;
    s.root = g.root;
    s.warnings = std::move(g.warnings);
    s.up = sg::dvec3(0.0, 1.0, 0.0);  // glTF's +Y up
    s.lights = std::move(g.lights);
    s.animations = std::move(g.animations);
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
    sg::GltfSaveOptions so;
    so.animations = scene.animations;
    sg::saveGltf(*root, path, so);
}

}  // namespace sgview
