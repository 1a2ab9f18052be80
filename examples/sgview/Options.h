// sgview's command line: what to show (files or a built-in scene), how (window, headless, info) and the view.
#pragma once
#include "sg/core/Math.h"
#include "sg/cull/CullSettings.h"
#include "sg/gl/PointShading.h"
#include "sg/viewer/Threading.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sgview {

// A command line that cannot be run: the message names the option and the value. sgview exits with 2.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct CameraSpec {
    sg::dvec3 eye, center, up;
};

struct Options {
    std::vector<std::string> files;
    std::string scene;  // "city" or "office" or "factory" (testbed/, docs/scenes.md) when no files are given
    int n = 0;          // city: N x N cells (default 32); office: R x R rooms (default 6)
    bool headless = false, info = false, overlay = false, help = false;
    bool refineAll = false;      // a tileset: every tile loaded and shown refined
    bool autoOccluders = false;  // occluders made from the geometry (sg::generateOccluders) for the occlusion pass
    int frames = 0;   // headless: frames rendered (default 1); window: quit after this many (0: run until closed)
    std::string out;  // headless: the picture (default sgview.png); window with --frames: frame K, written at exit
    std::optional<CameraSpec> camera;
    int width = 1280, height = 720;
    sg::CullStrategy strategy = sg::CullStrategy::Aabb;
    sg::OcclusionMode occlusion = sg::OcclusionMode::Adaptive;
    sg::ThreadingModel threading = sg::ThreadingModel::SingleThreaded;  // the viewer's threads (--threading)
    std::string save;                              // write the scene as glTF here and exit (--save)
    std::vector<std::pair<double, double>> picks;  // headless: pixels to pick in the last frame (--pick X,Y)
    bool json = false;                             // picks as JSON lines (--json)
    std::string style;                             // a 3D Tiles style file (--style)
    sg::PointShading points;                       // --point-size, --attenuate, --round, --line-width, --edl
    // The animations played: "all", a name or an index (--animation); empty: the first. Headless renders the pose at
    // `time` seconds (--time; 0 when not given); the window starts there and plays.
    std::string animation;
    double time = 0.0;
    bool timeGiven = false;
    // Reading a tileset over http(s): request headers ("Name: value", --header, repeatable), a PEM file of the
    // authorities to trust instead of the system's (--ca-file), and the disk cache: `cacheDir` (--cache DIR;
    // empty: ~/.cache/sgkit), off with --no-cache.
    std::vector<std::string> headers;
    std::string caFile;
    std::string cacheDir;
    bool noCache = false;
};

// Throws UsageError for an unknown option, a missing or malformed value, or a contradictory combination.
Options parseOptions(int argc, const char* const* argv);
const char* usageText();

}  // namespace sgview
