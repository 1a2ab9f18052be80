#include "map/Options.h"

#include "map/Atlas.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace sgmap {

namespace {

const char* kUsage =
    "usage: sgmap [--headless [--script FILE|-] [--overlay]] [--data DIR] [--size WxH] [--threading MODEL]\n"
    "  --headless      render offscreen and run a script (default: the built-in demo), one result line per command\n"
    "  --script FILE   the commands, one per line ('-': standard input):\n"
    "                    goto LON LAT HEIGHT_KM   zoom FACTOR   enter [ID]   back   pick X Y   pickgeo LON LAT\n"
    "                    screenshot FILE   stats   wait   frames N   overlay on|off\n"
    "  --data DIR      the converted levels (world.glb, us.glb, states/); default: the build tree's\n"
    "  --size WxH      window or picture size (default 1280x720)\n"
    "  --overlay       headless: draw the overlay into screenshots\n"
    "  --loader-nice N the loader thread's nice value, 0 (default: the program's priority) to 19\n"
    "  --threading MODEL  the viewer's threads: single (default), draw (a draw thread), cull-per-view,\n"
    "                  app-cull-draw (sg::ThreadingModel)\n"
    "  --frames N      window: quit after N frames;  --commands \"a;b\": window: commands run at start\n"
    "in the window: click picks, right click or B goes back up, scroll zooms (a region covering more than half\n"
    "  of the window is entered), drag pans, E enters the region in the centre, H the overlay, P a screenshot\n";

}  // namespace

int readCommandLine(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        const char* v = nullptr;
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (a == "--headless") {
            o.headless = true;
        } else if (a == "--overlay") {
            o.overlay = true;
        } else if (a == "--script" && (v = value())) {
            o.script = v;
        } else if (a == "--data" && (v = value())) {
            o.dataDir = v;
        } else if (a == "--commands" && (v = value())) {
            o.commands = v;
        } else if (a == "--loader-nice" && (v = value())) {
            o.loaderNice = std::atoi(v);
            if (o.loaderNice < 0 || o.loaderNice > 19) {
                std::fprintf(stderr, "sgmap: --loader-nice wants 0 to 19, not '%s'\n", v);
                return 2;
            }
        } else if (a == "--threading" && (v = value())) {
            try {
                o.threading = sg::parseThreadingModel(v);
            } catch (const std::invalid_argument&) {
                std::fprintf(stderr,
                             "sgmap: --threading wants single, draw, cull-per-view or app-cull-draw, not '%s'\n", v);
                return 2;
            }
        } else if (a == "--frames" && (v = value())) {
            o.frames = std::atoi(v);
            if (o.frames < 1) {
                std::fprintf(stderr, "sgmap: --frames needs a count of 1 or more, not '%s'\n", v);
                return 2;
            }
        } else if (a == "--size" && (v = value())) {
            if (std::sscanf(v, "%dx%d", &o.width, &o.height) != 2 || o.width < 16 || o.height < 16 || o.width > 8192 ||
                o.height > 8192) {
                std::fprintf(stderr, "sgmap: --size wants WxH between 16 and 8192, not '%s'\n", v);
                return 2;
            }
        } else {
            std::fprintf(stderr, "sgmap: unknown option or missing value: %s\n%s", a.c_str(), kUsage);
            return 2;
        }
    }
    return -1;
}

AtlasSettings atlasSettings(const Options& o) {
    AtlasSettings s;
    s.pager.loaderNice = o.loaderNice;
    return s;
}

std::string dataDirectory(const Options& o) {
    if (!o.dataDir.empty()) return o.dataDir;
#ifdef SGMAP_BUILD_DATA
    const std::filesystem::path built(SGMAP_BUILD_DATA);
    if (std::filesystem::exists(built / "levels" / "world.glb")) return (built / "levels").string();
    return (built / "generated").string();
#else
    return "mapdata";
#endif
}

std::string demoScript(bool generated) {
    if (generated)
        return "stats\nscreenshot sgmap-world.png\npick 640 360\nenter 840\nscreenshot sgmap-us.png\npick 640 360\n"
               "enter 01\nscreenshot sgmap-state.png\npick 640 360\nstats\nback\nback\nstats\n";
    return "# The world; zooming in on the United States until it covers over half of the window enters it;\n"
           "# Texas entered by command, a county picked, and back up.\n"
           "frames 30\n"
           "stats\n"
           "pickgeo -98.5 39.5\n"
           "screenshot sgmap-world.png\n"
           "goto -97 38 3500\n"
           "zoom 1.25\n"
           "wait\n"
           "frames 30\n"
           "stats\n"
           "pickgeo -99.5 31.5\n"
           "screenshot sgmap-us.png\n"
           "enter 48\n"
           "pickgeo -95.37 29.76\n"
           "screenshot sgmap-texas.png\n"
           "pick 640 360\n"
           "stats\n"
           "back\n"
           "back\n"
           "stats\n";
}

}  // namespace sgmap
