#include "sgview/Options.h"

#include "sg/core/Camera.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <utility>

namespace sgview {

namespace {

[[noreturn]] void bad(const std::string& option, const std::string& value, const std::string& why) {
    throw UsageError(option + " '" + value + "': " + why);
}

int parseInt(const std::string& option, const std::string& v, int lo, int hi) {
    errno = 0;
    char* end = nullptr;
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || errno == ERANGE || x < lo || x > hi)
        bad(option, v, "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    return int(x);
}

// Comma-separated finite numbers, exactly `count` of them.
std::vector<double> parseNumbers(const std::string& option, const std::string& v, size_t count, const char* form) {
    std::vector<double> out;
    const char* p = v.c_str();
    while (true) {  // a number, then a comma and another, or the end
        char* end = nullptr;
        errno = 0;
        const double x = std::strtod(p, &end);
        if (end == p || errno == ERANGE || !std::isfinite(x)) bad(option, v, std::string("expected ") + form);
        out.push_back(x);
        p = end;
        if (*p != ',') break;
        ++p;
    }
    if (*p != '\0' || out.size() != count) bad(option, v, std::string("expected ") + form);
    return out;
}

CameraSpec parseCamera(const std::string& v) {
    const char* form = "eye,center,up: 9 comma-separated numbers, e.g. 0,-10,5,0,0,0,0,0,1";
    const std::vector<double> x = parseNumbers("--camera", v, 9, form);
    CameraSpec c{{x[0], x[1], x[2]}, {x[3], x[4], x[5]}, {x[6], x[7], x[8]}};
    try {
        sg::Camera().setLookAt(c.eye, c.center, c.up);  // eye == centre, a zero up or one along the view
    } catch (const std::invalid_argument& e) {
        bad("--camera", v, e.what());
    }
    return c;
}

void parseSize(const std::string& v, int& w, int& h) {
    const size_t x = v.find('x');
    const char* form = "expected WxH with each from 1 to 16384, e.g. 1280x720";
    if (x == std::string::npos) bad("--size", v, form);
    const std::string a = v.substr(0, x), b = v.substr(x + 1);
    for (const std::string& s : {a, b})
        if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) bad("--size", v, form);
    try {
        w = parseInt("--size", a, 1, 16384);
        h = parseInt("--size", b, 1, 16384);
    } catch (const UsageError&) {
        bad("--size", v, form);
    }
}

}  // namespace

Options parseOptions(int argc, const char* const* argv) {
    Options o;
    bool frames = false, out = false, n = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(a + " needs a value");
            return argv[++i];
        };
        if (a == "--help" || a == "-h")
            o.help = true;
        else if (a == "--headless")
            o.headless = true;
        else if (a == "--json")
            o.json = true;
        else if (a == "--info")
            o.info = true;
        else if (a == "--refine-all")
            o.refineAll = true;
        else if (a == "--auto-occluders")
            o.autoOccluders = true;
        else if (a == "--overlay")
            o.overlay = true;
        else if (a == "--no-cache")
            o.noCache = true;
        else if (a == "--header") {
            const std::string v = value();
            const size_t colon = v.find(':');
            if (colon == 0 || colon == std::string::npos || v.find_first_of("\r\n") != std::string::npos)
                bad(a, v, "expected \"Name: value\", e.g. \"Authorization: Bearer TOKEN\"");
            o.headers.push_back(v);
        } else if (a == "--ca-file" || a == "--cache") {
            std::string& to = a == "--ca-file" ? o.caFile : o.cacheDir;
            to = value();
            if (to.empty()) bad(a, to, a == "--ca-file" ? "expected a PEM file" : "expected a directory");
        } else if (a == "--scene") {
            o.scene = value();
            if (o.scene != "city" && o.scene != "office" && o.scene != "factory" && o.scene != "materials" &&
                o.scene != "figures")
                bad(a, o.scene, "the built-in scenes are city, office, factory, materials and figures");
        } else if (a == "--n") {
            o.n = parseInt(a, value(), 1, 1000);
            n = true;
        } else if (a == "--frames") {
            o.frames = parseInt(a, value(), 1, 1000000);
            frames = true;
        } else if (a == "--out") {
            o.out = value();
            if (o.out.empty()) bad(a, o.out, "expected a file name");
            out = true;
        } else if (a == "--save") {
            o.save = value();
            const size_t dot = o.save.rfind('.');
            const std::string ext = dot == std::string::npos ? "" : o.save.substr(dot);
            if (ext != ".glb" && ext != ".gltf") bad(a, o.save, "expected a .glb or .gltf file name");
        } else if (a == "--style") {
            o.style = value();
            if (o.style.empty()) bad(a, o.style, "expected a style file (JSON)");
        } else if (a == "--pick") {
            const std::string v = value();
            const std::vector<double> xy = parseNumbers(a, v, 2, "X,Y (a pixel, y down)");
            o.picks.emplace_back(xy[0], xy[1]);
        } else if (a == "--point-size" || a == "--line-width" || a == "--attenuate") {
            const std::string v = value();
            const double x = parseNumbers(a, v, 1, "pixels")[0];
            if (!(x >= 1.0 && x <= 64.0)) bad(a, v, "pixels from 1 to 64");
            if (a == "--point-size") o.points.pointSize = float(x);
            if (a == "--line-width") o.points.lineWidth = float(x);
            if (a == "--attenuate") {
                o.points.attenuate = true;
                o.points.maxPointSize = float(x);
            }
        } else if (a == "--animation") {
            o.animation = value();
            if (o.animation.empty()) bad(a, o.animation, "expected all, a name or an index");
        } else if (a == "--time") {
            const std::string v = value();
            o.time = parseNumbers(a, v, 1, "seconds")[0];
            if (!(o.time >= 0.0 && o.time <= 1e6)) bad(a, v, "seconds from 0 to 1e6");
            o.timeGiven = true;
        } else if (a == "--round")
            o.points.round = true;
        else if (a == "--edl")
            o.points.eyeDome = true;
        else if (a == "--camera")
            o.camera = parseCamera(value());
        else if (a == "--size")
            parseSize(value(), o.width, o.height);
        else if (a == "--strategy" || a == "--occlusion") {
            const std::string v = value();
            try {
                if (a == "--strategy")
                    o.strategy = sg::parseStrategy(v);
                else
                    o.occlusion = sg::parseOcclusionMode(v);
            } catch (const std::invalid_argument& e) {
                bad(a, v, e.what());
            }
        } else if (a == "--threading") {
            const std::string v = value();
            try {
                o.threading = sg::parseThreadingModel(v);
            } catch (const std::invalid_argument& e) {
                bad(a, v, e.what());
            }
        } else if (a.size() > 1 && a[0] == '-')
            throw UsageError("unknown option '" + a + "'");
        else
            o.files.push_back(a);
    }
    if (o.help) return o;
    if (o.points.attenuate && o.points.maxPointSize < o.points.pointSize)
        throw UsageError("--attenuate " + std::to_string(int(o.points.maxPointSize)) +
                         ": the largest size is below --point-size");
    if (o.files.empty() && o.scene.empty())
        throw UsageError("nothing to show: give FILE... or --scene city|office|factory|materials|figures");
    if (!o.files.empty() && !o.scene.empty()) throw UsageError("give either FILE... or --scene, not both");
    if (n && o.scene.empty()) throw UsageError("--n sizes a built-in scene: it needs --scene");
    if (out && !o.headless && !frames)
        throw UsageError("--out in the window needs --frames K (the picture is frame K; P or F12 save screenshots)");
    if (o.info && o.headless) throw UsageError("--info prints a summary and renders nothing: drop --headless");
    if (!o.save.empty() && (o.headless || o.info))
        throw UsageError("--save writes the scene and exits: drop --headless and --info");
    if (!o.picks.empty() && !o.headless) throw UsageError("--pick is for --headless (in the window, click)");
    if (o.json && o.picks.empty()) throw UsageError("--json prints picks as JSON: give --pick X,Y too");
    for (const auto& [x, y] : o.picks)
        if (x < 0 || y < 0 || x >= o.width || y >= o.height)
            bad("--pick", std::to_string(int(x)) + "," + std::to_string(int(y)), "the pixel is outside the picture");
    if (o.refineAll && !o.scene.empty())
        throw UsageError("--refine-all loads every tile of a tileset: give a tileset.json, not --scene");
    const bool network = !o.headers.empty() || !o.caFile.empty() || !o.cacheDir.empty() || o.noCache;
    if (network && o.files.empty()) throw UsageError("--header, --ca-file and --cache are for a tileset's URL");
    if (o.noCache && !o.cacheDir.empty()) throw UsageError("--cache DIR and --no-cache: give one");
    if (!n) o.n = o.scene == "office" ? 6 : o.scene == "figures" ? 3 : 32;
    if (!frames && o.headless) o.frames = 1;
    if (!out && o.headless) o.out = "sgview.png";
    return o;
}

const char* usageText() {
    return "usage: sgview FILE... | --scene city|office|factory|materials|figures [--n N]\n"
           "              [--headless [--overlay] [--pick X,Y [--json]]] [--frames K [--out frame.png]] [--info]\n"
           "              [--refine-all] [--auto-occluders]\n"
           "              [--camera ex,ey,ez,cx,cy,cz,ux,uy,uz] [--size WxH] [--strategy S] [--occlusion M]\n"
           "              [--threading MODEL] [--style STYLE.json]\n"
           "              [--point-size PX] [--attenuate MAXPX] [--round] [--line-width PX] [--edl]\n"
           "              [--animation all|NAME|INDEX] [--time T]\n"
           "              [--header \"NAME: VALUE\"] [--ca-file CA.pem] [--cache DIR | --no-cache]\n"
           "  FILE...            glTF 2.0 files (.gltf, .glb), shown together, or one 3D Tiles tileset.json (a path "
           "or\n"
           "                     an http(s) URL): its tiles load as the view needs them; or a scan (.las, .ply)\n"
           "  --refine-all       a tileset: load every tile and show it fully refined (with --info or --headless too)\n"
           "  --auto-occluders   make occluders from the geometry (boxes inside closed meshes, large flat faces) for\n"
           "                     the occlusion pass (a tileset: each tile as it is read); authored ones stay\n"
           "  --scene city       the benchmark city, N x N cells (--n, default 32); office: R x R rooms (default 6);\n"
           "                     factory: the walkthrough site; materials: physical materials (--n not used);\n"
           "                     figures: N x N walking skinned figures (default 3)\n"
           "  --headless         render offscreen (no display needed) and write the last frame to --out (sgview.png)\n"
           "  --overlay          headless: draw the stats overlay into the picture\n"
           "  --frames K         headless: frames rendered (default 1); window: quit after K frames\n"
           "  --out frame.png    headless: the picture (default sgview.png); window: frame K, written at exit\n"
           "  --camera E,C,U     eye, centre and up (default: the whole scene framed from above one corner)\n"
           "  --size WxH         picture or window size (default 1280x720)\n"
           "  --strategy S       culling: none, sphere, aabb (default), sphere-sphere, center-box\n"
           "  --occlusion M      when occlusion culling runs: off, every-frame, adaptive (default)\n"
           "  --threading MODEL  the viewer's threads: single (default), draw (a draw thread), cull-per-view,\n"
           "                     app-cull-draw (sg::ThreadingModel)\n"
           "  --pick X,Y         headless: print the node path of what is at pixel (X, Y) (y down; repeatable), and\n"
           "                     the features there with their properties\n"
           "  --json             print each pick as one JSON object on its own line\n"
           "  --style FILE.json  a 3D Tiles style (show, color, conditions over the features' properties)\n"
           "  --point-size PX    points drawn PX pixels wide (default 2)\n"
           "  --attenuate MAXPX  points as large as their spacing (a tile's geometric error) looks, from --point-size\n"
           "                     to MAXPX pixels\n"
           "  --round            points as discs (else squares)\n"
           "  --line-width PX    lines and outlines PX pixels wide (default 1)\n"
           "  --edl              eye-dome lighting: edges shaded by depth (points without normals get their shape)\n"
           "  --animation A      the animations played: all, a name or an index (default: the first)\n"
           "  --time T           headless: the pose at T seconds (default 0); window: start there\n"
           "  --header H         a tileset over http(s): send H (\"Name: value\") with every request (repeatable);\n"
           "                     a query string on the tileset's URL (a key) goes with every tile of its server\n"
           "  --ca-file CA.pem   trust the authorities in CA.pem (not the system's) for https; certificates are\n"
           "                     always verified\n"
           "  --cache DIR        keep what is read over http(s) in DIR (default ~/.cache/sgkit) for the next run\n"
           "  --no-cache         read everything from the server\n"
           "  --save FILE.glb    write the scene as glTF (.glb or .gltf; +Z up turned to glTF's +Y) and exit\n"
           "  --info             print node counts by kind, triangles, bounds, memory and warnings, then exit\n"
           "keys in the window:\n"
           "  1 trackball (left drag orbits, right or middle drag pans, scroll zooms)\n"
           "  2 fly (WASD moves, Q/E down/up, left drag looks, scroll sets the speed, shift runs)\n"
           "  3 walk (as fly, on the level; walls stop you, you keep your height above the ground)\n"
           "  C culling strategy   O occlusion mode   Tab stats overlay   Home reset view\n"
           "  P or F12 screenshot (sgview-NNNN.png)   click picks   H this help   Escape quits\n"
           "  Space pauses or resumes the animations\n";
}

}  // namespace sgview
