// sgmapconv: converts the map's source data (tools/fetch-map-data.sh) into the map's levels as .glb files,
// or writes the generated stand-in map; prints the counts, the worst triangulation area error and the time.
#include "map/data/MapConvert.h"

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

static void usage() {
    std::fprintf(stderr,
                 "usage: sgmapconv IN_DIR OUT_DIR     convert countries-50m.json and counties-10m.json\n"
                 "       sgmapconv --generated OUT_DIR [SEED]   write the generated stand-in map\n"
                 "options: --height KM (prism height of a county; states x2, countries x8; default 10)\n"
                 "         --height-by-area (heights from a quarter to all of it by the square root of the area)\n");
}

int main(int argc, char** argv) {
    sg::MapLevelOptions options;
    bool generated = false;
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--generated") {
            generated = true;
        } else if (a == "--height" && i + 1 < argc) {
            options.height = std::atof(argv[++i]);
            if (!(options.height > 0.0)) {
                std::fprintf(stderr, "sgmapconv: --height must be a positive number\n");
                return 2;
            }
        } else if (a == "--height-by-area") {
            options.heightEncodesArea = true;
        } else if (a == "-h" || a == "--help") {
            usage();
            return 0;
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "sgmapconv: unknown option %s\n", a.c_str());
            usage();
            return 2;
        } else {
            args.push_back(a);
        }
    }
    if ((generated && (args.empty() || args.size() > 2)) || (!generated && args.size() != 2)) {
        usage();
        return 2;
    }
    try {
        const sg::MapConvertReport r =
            generated ? sg::generateFallbackMap(args[0], args.size() > 1 ? uint32_t(std::stoul(args[1])) : 1u)
                      : sg::convertMapData(args[0], args[1], options);
        std::printf("sgmapconv: %zu files, %zu regions (%zu without triangles), %zu triangles in %.2f s\n", r.files,
                    r.regions, r.emptyRegions, r.triangles, r.seconds);
        for (const auto& p : r.withoutArea) std::printf("sgmapconv: note: %s\n", p.c_str());
        for (const auto& p : r.problems) std::printf("sgmapconv: problem: %s\n", p.c_str());
        std::printf("sgmapconv: worst area error %.3g (%s)\n", r.maxAreaError, r.worst.c_str());
        return r.problems.empty() ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgmapconv: %s\n", e.what());
        return 1;
    }
}
