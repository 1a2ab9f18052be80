#include "factory/Options.h"

#include "factory/KeyScript.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace factory {

namespace {
std::string value(int argc, char** argv, int& i) {
    const std::string name = argv[i];
    if (i + 1 >= argc) throw OptionError(name + " needs a value");
    return argv[++i];
}
long integer(const std::string& name, const std::string& v, long lo, long hi) {
    char* end = nullptr;
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || x < lo || x > hi)
        throw OptionError(name + " '" + v + "' is not an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return x;
}
}  // namespace

const char* usage() {
    return "usage: factory [--headless] [--frames N] [--size WxH] [--budget-ms MS] [--out-dir DIR] [--json]\n"
           "               [--cache-dir DIR] [--no-lighting] [--camera ex,ey,ez,cx,cy,cz] [--keys \"...\"]\n"
           "               [--background-load none|spin] [--free-run] [--threading MODEL] [--help]\n"
           "  --headless         the scripted walkthrough offscreen: pictures, per-frame CSV, the paper's table\n"
           "                     (without it: the site in a window, 1070x865 by default; needs a display or xvfb-run)\n"
           "  --frames N         headless: the path's length (default 480); window: quit after N frames, writing\n"
           "                     the last to DIR/factory-window.png (each frame then moves 1/30 s)\n"
           "  --size WxH         picture or window size (default 1070x865, the paper's)\n"
           "  --budget-ms MS     the frame time the budget and stress LOD methods aim at (default 33); they hold it:\n"
           "                     a frame done early waits, as at a fixed frame rate   --free-run  they do not wait\n"
           "  --out-dir DIR      pictures, CSV and screenshots (default .)   --json  headless: the summary as JSON\n"
           "  --cache-dir DIR    where the baked lighting is kept   --no-lighting  the site unlit (no bake)\n"
           "  --background-load spin  a thread busy on another core all along: the walkthrough on a busy machine\n"
           "  --threading MODEL  the viewer's threads: single (default), draw (a draw thread), cull-per-view,\n"
           "                     app-cull-draw (sg::ThreadingModel); headless, the methods share one context and\n"
           "                     each frame is compared at full detail, so the stages of a frame never overlap\n"
           "  --camera E,C       window: start at eye E looking at centre C (+Z up; default: the walk's start)\n"
           "  --keys \"...\"       window: keys replayed, a token a frame: W A S D (W*30: held 30 frames), F M O P\n"
           "                     H Esc, drag:DX,DY, click:X,Y, wait*N\n"
           "keys in the window:\n"
           "  W/A/S/D move, mouse drag looks, a click shows the building or machine there (highlighted)\n"
           "  F walk (collisions, 1.7 m over the ground) / fly\n"
           "  M LOD: static / budget / stress   O occlusion on/off   P or F12 screenshot   H overlay   Esc quits\n"
           "  Q/E down/up (flying), shift runs, the mouse wheel sets the speed\n";
}

Options parseOptions(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        if (k == "--headless") {
            o.headless = true;
        } else if (k == "--json") {
            o.json = true;
        } else if (k == "--frames") {
            o.frames = int(integer(k, value(argc, argv, i), 10, 100000));
            o.framesGiven = true;
        } else if (k == "--size") {
            const std::string v = value(argc, argv, i);
            int w = 0, h = 0;
            char tail = 0;
            if (std::sscanf(v.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192)
                throw OptionError("--size '" + v + "' is not WxH with both in 16..8192");
            o.width = w;
            o.height = h;
        } else if (k == "--budget-ms") {
            const std::string v = value(argc, argv, i);
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (v.empty() || *end != '\0' || !std::isfinite(x) || x < 1.0 || x > 10000.0)
                throw OptionError("--budget-ms '" + v + "' is not a number of milliseconds in 1..10000");
            o.budgetMs = x;
        } else if (k == "--out-dir") {
            o.outDir = value(argc, argv, i);
            if (o.outDir.empty()) throw OptionError("--out-dir is empty");
        } else if (k == "--cache-dir") {
            o.cacheDir = value(argc, argv, i);
            if (o.cacheDir.empty()) throw OptionError("--cache-dir is empty");
        } else if (k == "--free-run") {
            o.freeRun = true;
        } else if (k == "--no-lighting") {
            o.lighting = false;
        } else if (k == "--background-load") {
            const std::string v = value(argc, argv, i);
            try {
                o.backgroundLoad = scenes::BackgroundLoad::parse(v);
            } catch (const std::invalid_argument&) {
                throw OptionError("--background-load '" + v + "' is not none or spin");
            }
        } else if (k == "--threading") {
            const std::string v = value(argc, argv, i);
            try {
                o.threading = sg::parseThreadingModel(v);
            } catch (const std::invalid_argument&) {
                throw OptionError("--threading '" + v + "' is not single, draw, cull-per-view or app-cull-draw");
            }
        } else if (k == "--jitter-draws") {
            o.jitterDraws = int(integer(k, value(argc, argv, i), 2, 10000));
        } else if (k == "--help" || k == "-h") {  // the window's options: --help, --camera, --keys
            o.help = true;
        } else if (k == "--camera") {
            const std::string v = value(argc, argv, i);
            double x[6];
            char tail = 0;
            if (std::sscanf(v.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf%c", &x[0], &x[1], &x[2], &x[3], &x[4], &x[5], &tail) !=
                    6 ||
                !std::all_of(x, x + 6, [](double d) { return std::isfinite(d); }))
                throw OptionError("--camera '" + v + "' is not eye and centre, 6 comma-separated numbers");
            o.camera = true;
            o.eye = sg::dvec3(x[0], x[1], x[2]);
            o.center = sg::dvec3(x[3], x[4], x[5]);
            if (glm::length(o.center - o.eye) == 0.0) throw OptionError("--camera '" + v + "': the eye is the centre");
        } else if (k == "--keys") {
            o.keys = value(argc, argv, i);
            try {
                parseKeyScript(o.keys);
            } catch (const std::invalid_argument& e) {
                throw OptionError(std::string("--keys: ") + e.what());
            }
        } else {
            throw OptionError("unknown option '" + k + "'");
        }
    }
    if (o.headless && (o.camera || !o.keys.empty()))
        throw OptionError(std::string(o.camera ? "--camera" : "--keys") + " is for the window: drop --headless");
    return o;
}

int readCommandLine(int argc, char** argv, Options& o) {
    try {
        o = parseOptions(argc, argv);
        if (o.help) {
            std::fputs(usage(), stdout);
            return 0;
        }
        std::filesystem::create_directories(o.outDir);
    } catch (const OptionError& e) {
        std::fprintf(stderr, "factory: %s\n(factory --help lists the options)\n", e.what());
        return 2;
    } catch (const std::filesystem::filesystem_error& e) {
        std::fprintf(stderr, "factory: --out-dir '%s' cannot be created: %s\n", o.outDir.c_str(), e.what());
        return 2;
    }
    return -1;
}

}  // namespace factory
