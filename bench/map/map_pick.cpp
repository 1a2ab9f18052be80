// map_pick: the map's pickgeo against point-in-polygon on the source polygons at the world, U.S. and Texas
// levels (MapPickCheck.h); one JSON line per level; exit 1 when a point away from every border is picked wrong.
#include "MapPickCheck.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#ifndef SGKIT_MAP_DATA_DIR
#define SGKIT_MAP_DATA_DIR "mapdata"
#endif

int main(int argc, char** argv) {
    int points = 1000;
    uint32_t seed = 1;
    std::string levels = SGKIT_MAP_DATA_DIR "/levels", source = SGKIT_MAP_DATA_DIR "/source";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc || (a != "--points" && a != "--seed" && a != "--data" && a != "--source")) {
            std::fprintf(stderr,
                         "usage: map_pick [--points N=1000] [--seed S=1] [--data LEVELS_DIR] "
                         "[--source SOURCE_DIR]\n");
            return 2;
        }
        const std::string v = argv[++i];
        if (a == "--points") points = std::atoi(v.c_str());
        if (a == "--seed") seed = uint32_t(std::strtoul(v.c_str(), nullptr, 10));
        if (a == "--data") levels = v;
        if (a == "--source") source = v;
    }
    try {
        sgmap::Atlas atlas(levels);
        if (atlas.generated()) {
            std::fprintf(stderr,
                         "map_pick: %s is the generated stand-in map (no longitudes); run the map-data target\n",
                         levels.c_str());
            return 2;
        }
        bool allFar = true;
        for (const sgmap::MapPickLevel& l : sgmap::checkMapPicks(atlas, source, points, seed)) {
            std::printf("%s\n", l.json().c_str());
            allFar = allFar && l.farCorrect == l.farPoints;
        }
        return allFar ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "map_pick: %s\n", e.what());
        return 2;
    }
}
