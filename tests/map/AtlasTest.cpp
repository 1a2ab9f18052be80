// The map's levels on the generated map (no GL): entering pages a level in on the loader thread, back frees it,
// picking answers at the current level only, a bad file leaves the map usable, and enter/back cycles with loads
// in flight leave nothing behind.
#include "map/MapTestData.h"

#include <filesystem>
#include <fstream>
#include <random>

using namespace sgmap;
using namespace maptest;

TEST(Atlas, StartsAtTheWorldWithTheUnitedStatesPaged) {
    Atlas atlas(generatedDir());
    EXPECT_EQ(atlas.level().name, "world");
    EXPECT_EQ(atlas.depth(), 1u);
    EXPECT_TRUE(atlas.generated());
    const int us = atlas.level().findId("840");
    ASSERT_GE(us, 0);
    const Region& r = atlas.level().regions[size_t(us)];
    EXPECT_EQ(r.kind, "country");
    ASSERT_NE(r.paged, nullptr);
    EXPECT_EQ(r.paged->state(), sg::PagedLOD::State::Unloaded);
    EXPECT_EQ(r.paged->trigger(), sg::PagedLOD::Trigger::Command);
    // Countries without a next level are plain.
    size_t paged = 0;
    for (const Region& x : atlas.level().regions) paged += x.paged != nullptr;
    EXPECT_EQ(paged, 1u);
}

TEST(Atlas, EnterPagesTheLevelInAndBackFreesIt) {
    Atlas atlas(generatedDir());
    uint64_t frame = 0;
    const size_t worldBytes = atlas.bytesLoaded();
    const size_t us = size_t(atlas.level().findId("840"));
    sg::PagedLOD* paged = atlas.level().regions[us].paged;
    ASSERT_EQ(atlas.enter(us), "");
    EXPECT_EQ(atlas.entering(), int(us));
    EXPECT_EQ(atlas.level().name, "world");  // not before an update attaches it
    ASSERT_TRUE(settle(atlas, frame).entered);
    EXPECT_EQ(atlas.level().name, "us");
    EXPECT_EQ(atlas.level().parent, "840");
    EXPECT_EQ(atlas.depth(), 2u);
    EXPECT_EQ(paged->state(), sg::PagedLOD::State::Loaded);
    for (const Region& r : atlas.level().regions) EXPECT_EQ(r.kind, "state");
    EXPECT_EQ(atlas.pager().stats().loads, 1u);
    EXPECT_EQ(atlas.pager().stats().resident, 1u);
    EXPECT_GT(atlas.pager().stats().bytesResident, 0u);
    EXPECT_EQ(atlas.bytesLoaded(), worldBytes + atlas.level().bytes);

    EXPECT_EQ(atlas.back(), "");
    EXPECT_EQ(atlas.level().name, "world");
    EXPECT_EQ(paged->state(), sg::PagedLOD::State::Unloaded);
    EXPECT_EQ(paged->detail(), nullptr);
    EXPECT_EQ(atlas.pager().stats().unloads, 1u);
    EXPECT_EQ(atlas.pager().stats().resident, 0u);
    EXPECT_EQ(atlas.pager().stats().bytesResident, 0u);
    EXPECT_EQ(atlas.bytesLoaded(), worldBytes);
    EXPECT_NE(atlas.back(), "");  // nothing above the world
}

TEST(Atlas, PicksTheRegionOfTheCurrentLevelOnly) {
    Atlas atlas(generatedDir());
    uint64_t frame = 0;
    const size_t us = size_t(atlas.level().findId("840"));
    int other = 0;
    while (size_t(other) == us) ++other;
    const sg::dvec3 elsewhere = insidePoint(atlas, size_t(other));
    EXPECT_EQ(atlas.pickGeo(elsewhere.x, elsewhere.y), other);

    ASSERT_TRUE(enterId(atlas, "840", frame));
    // A state's point: the state at the U.S. level, not the country around it.
    const size_t s = 1;
    const sg::dvec3 p = insidePoint(atlas, s);
    EXPECT_EQ(atlas.pickGeo(p.x, p.y), int(s));
    EXPECT_EQ(atlas.level().regions[s].kind, "state");
    // The other countries are hidden (the U.S. level need not share their projection): nothing there.
    EXPECT_EQ(atlas.pickGeo(elsewhere.x, elsewhere.y), -1);

    const std::string stateId = atlas.level().regions[s].id;
    ASSERT_TRUE(enterId(atlas, stateId, frame));
    EXPECT_EQ(atlas.level().name, "state");
    const int county = atlas.pickGeo(p.x, p.y);
    ASSERT_GE(county, 0);
    EXPECT_EQ(atlas.level().regions[size_t(county)].kind, "county");
    EXPECT_EQ(atlas.level().regions[size_t(county)].id.substr(0, 2), stateId);
    // Another state, still drawn around the one entered, is not of this level.
    ASSERT_EQ(atlas.back(), "");
    const sg::dvec3 q = insidePoint(atlas, 0);
    ASSERT_TRUE(enterId(atlas, stateId, frame));
    EXPECT_EQ(atlas.pickGeo(q.x, q.y), -1);

    ASSERT_EQ(atlas.back(), "");
    ASSERT_EQ(atlas.back(), "");
    EXPECT_EQ(atlas.pickGeo(elsewhere.x, elsewhere.y), other);
    EXPECT_EQ(atlas.pickGeo(p.x, p.y), int(us));
}

TEST(Atlas, HighlightSwapsTheRegionsMaterialAndRestoresIt) {
    Atlas atlas(generatedDir());
    Region& r = const_cast<Region&>(atlas.level().regions[3]);
    const sg::Material* own = r.geometries[0]->material();
    atlas.highlight(3);
    EXPECT_NE(r.geometries[0]->material(), own);
    EXPECT_EQ(atlas.highlighted(), 3);
    atlas.highlight(-1);
    EXPECT_EQ(r.geometries[0]->material(), own);
    EXPECT_EQ(atlas.highlighted(), -1);
}

TEST(Atlas, EnteringARegionWithoutALevelSaysWhy) {
    Atlas atlas(generatedDir());
    const size_t plain = atlas.level().findId("840") == 0 ? 1 : 0;
    const std::string why = atlas.enter(plain);
    EXPECT_NE(why.find(atlas.level().regions[plain].name), std::string::npos) << why;
    EXPECT_NE(why.find("no level below"), std::string::npos) << why;
    EXPECT_EQ(atlas.entering(), -1);
}

TEST(Atlas, ABadLevelFileIsReportedAndTheMapStaysUsable) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("sgmap_bad_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::copy(generatedDir(), dir, fs::copy_options::recursive);
    std::ofstream(dir / "states" / "01.glb", std::ios::binary) << "glTF not really";
    {
        Atlas atlas(dir.string());
        uint64_t frame = 0;
        ASSERT_TRUE(enterId(atlas, "840", frame));
        const int bad = atlas.level().findId("01");
        ASSERT_GE(bad, 0);
        ASSERT_EQ(atlas.enter(size_t(bad)), "");
        const Atlas::Step s = settle(atlas, frame);
        EXPECT_FALSE(s.entered);
        EXPECT_NE(s.error.find("01.glb"), std::string::npos) << s.error;
        EXPECT_EQ(atlas.level().name, "us");
        EXPECT_EQ(atlas.pager().stats().failures, 1u);
        // Another state still enters, and the bad one can be tried again.
        ASSERT_TRUE(enterId(atlas, "02", frame));
        EXPECT_EQ(atlas.level().parent, "02");
        ASSERT_EQ(atlas.back(), "");
        ASSERT_EQ(atlas.enter(size_t(bad)), "");
        EXPECT_FALSE(settle(atlas, frame).entered);
    }
    fs::remove_all(dir);
}

TEST(Atlas, EnterAndBackCyclesWithLoadsInFlightLeaveNothingBehind) {
    Atlas atlas(generatedDir());
    const size_t worldBytes = atlas.bytesLoaded();
    std::mt19937 rnd(7);
    uint64_t frame = 0;
    int entered = 0;
    for (int i = 0; i < 400; ++i) {
        const int op = int(rnd() % 4);
        if (op == 0 && atlas.entering() < 0) {
            std::vector<size_t> paged;
            for (size_t k = 0; k < atlas.level().regions.size(); ++k)
                if (atlas.level().regions[k].paged) paged.push_back(k);
            if (!paged.empty()) {
                EXPECT_EQ(atlas.enter(paged[rnd() % paged.size()]), "");
            }
        } else if (op == 1) {
            atlas.back();  // stops a load in flight, or goes up; at the world it says why
        } else if (op == 2) {
            atlas.pager().waitIdle();  // else the next update comes while the load is still running
        }
        entered += atlas.update({++frame, frame / 60.0}).entered;
        ASSERT_LE(atlas.depth(), 3u);
        ASSERT_EQ(atlas.pager().stats().resident, atlas.depth() - 1);
    }
    EXPECT_GT(entered, 20);  // the cycles did reach the levels
    while (atlas.entering() >= 0 || atlas.depth() > 1) atlas.back();
    atlas.pager().waitIdle();
    atlas.update({++frame, frame / 60.0});
    EXPECT_EQ(atlas.level().name, "world");
    EXPECT_EQ(atlas.pager().stats().resident, 0u);
    EXPECT_EQ(atlas.pager().stats().bytesResident, 0u);
    EXPECT_EQ(atlas.bytesLoaded(), worldBytes);
    for (const Region& r : atlas.level().regions) {
        if (r.paged) {
            EXPECT_NE(r.paged->state(), sg::PagedLOD::State::Loaded);
        }
    }
}
