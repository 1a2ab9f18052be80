// pickgeo on the real map (world, United States, Texas) against point-in-polygon on the source polygons:
// 200 random points per level; every point farther than one pixel from a border picks the source's region
// (or none over the sea and outside Texas). Skips, saying why, without the map-data target's files.
#include "MapPickCheck.h"
#include "OutsideTools.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

namespace {

TEST(MapPick, PickGeoMatchesSourcePolygonsAwayFromBorders) {
    namespace fs = std::filesystem;
    const fs::path source = SGKIT_MAP_SOURCE_DIR, levels = SGKIT_MAP_LEVELS_DIR;
    if (!fs::exists(source / "countries-50m.json") || !fs::exists(source / "counties-10m.json"))
        SG_SKIP_OR_FAIL("no map source data in " << source << " (build the map-data target)");
    if (!fs::exists(levels / "world.glb") || !fs::exists(levels / "us.glb") || !fs::exists(levels / "states/48.glb"))
        SG_SKIP_OR_FAIL("no converted map levels in " << levels << " (build the map-data target)");
    sgmap::Atlas atlas(levels.string());
    ASSERT_FALSE(atlas.generated());
    const auto result = sgmap::checkMapPicks(atlas, source.string(), 200, 1);
    ASSERT_EQ(result.size(), 3u);
    for (const sgmap::MapPickLevel& l : result) {
        std::printf("[ map pick ] %s\n", l.json().c_str());
        EXPECT_EQ(l.points, 200) << l.level;
        EXPECT_EQ(l.farCorrect, l.farPoints) << l.json();
        // Not vacuous: most points are away from borders, and both regions and none are expected.
        EXPECT_GT(l.farPoints, 150) << l.level;
        EXPECT_GT(l.inRegion, 30) << l.level;
        EXPECT_LT(l.inRegion, 190) << l.level;
        EXPECT_GT(l.regionsHit, 20) << l.level;
    }
    EXPECT_EQ(atlas.depth(), 1u);
}

}  // namespace
