// MapPickCheck: the map's pickgeo (Atlas::pickGeo) at the world, U.S. and Texas levels compared with
// point-in-polygon on the source polygons, for random points, shared by the map_pick benchmark and its test.
#pragma once
#include "map/Atlas.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sgmap {

// One point whose pick differs from the source's answer.
struct MapPickMiss {
    double lon = 0.0, lat = 0.0;
    std::string expected, got;  // region ids (names for regions with an empty or shared id); "none"
    double borderKm = 0.0;      // distance to the nearest border in the level's plane
};

// One level's count. A point nearer a border than one pixel (the level's extent / 1280) is "near" and counted
// apart: the mesh may differ from the source there (positions are floats, self-crossing rings are split, and
// top faces triangulated in degrees stop at chords where flips could not mend them).
struct MapPickLevel {
    std::string level;  // "world", "us", "state 48"
    int points = 0, farPoints = 0, farCorrect = 0, nearPoints = 0, nearCorrect = 0;
    int inRegion = 0;    // points the source puts in a region (the others expect none)
    int regionsHit = 0;  // distinct regions among them
    double pixelKm = 0.0;
    double msPerPick = 0.0;              // the second pass over the points (the first builds the meshes' trees)
    double msFirstPass = 0.0;            // the whole first pass
    std::vector<MapPickMiss> wrong;      // the first five points away from borders picked wrong
    std::vector<MapPickMiss> nearWrong;  // the five near points picked wrong farthest from a border
    std::string json() const;            // one line
};

// Draws `points` random points (portable generator, `seed`) per level: the world (uniform on the sphere), the
// United States (half uniform in the union of its states' and territories' longitude/latitude boxes, Alaska's
// across 180 degrees, half in a box drawn uniformly so that the small territories get points), Texas (its box). The
// truth is the even-odd rule over each source region's rings (outer and holes), projected by the region's own
// projection (so the antimeridian and the U.S. insets are the source's geography, not what pickGeo assumes). `atlas`
// must be at the world level of the real data; it is left there. Throws std::runtime_error when a level cannot be
// entered.
std::vector<MapPickLevel> checkMapPicks(Atlas& atlas, const std::string& sourceDir, int points, uint32_t seed);

}  // namespace sgmap
