// OcclusionMethod::Auto (the default): the map over a city seen across its lower roofs, where the tree's
// nearest occluders leave most of the next ones showing; the tree in streets and rooms, where they hide them.
// Either way it draws exactly the unculled render's pixels.
#include "Scaled.h"
#include "sg/cull/CullTraversal.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Office.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
// Frames of the path (every `step`th) that built the map, and the geometries drawn with each method.
struct Picks {
    int map = 0, frames = 0;
    double autoGeoms = 0, treeGeoms = 0, mapGeoms = 0;
};

template <class CameraAt>
Picks picks(const Scene& s, int frames, int step, CameraAt at) {
    Picks p;
    CullTraversal a, t, m;
    DrawList dl;
    for (int f = 0; f < frames; f += step) {
        const Camera cam = at(f);
        CullSettings set;  // the default method: Auto
        set.occlusion.mode = OcclusionMode::EveryFrame;
        CullStats st;
        a.cull(s, cam, set, dl, st);
        p.map += st.occlusionMap;
        p.frames++;
        p.autoGeoms += double(st.geometries);
        set.occlusion.method = OcclusionMethod::Tree;
        CullStats tt;
        t.cull(s, cam, set, dl, tt);
        EXPECT_FALSE(tt.occlusionMap);
        p.treeGeoms += double(tt.geometries);
        set.occlusion.method = OcclusionMethod::Hom;
        CullStats mm;
        m.cull(s, cam, set, dl, mm);
        EXPECT_TRUE(mm.occlusionMap);
        p.mapGeoms += double(mm.geometries);
    }
    return p;
}
}  // namespace

TEST(OcclusionAuto, MapOverTheCityTreeInItsStreetsAndInRooms) {
    EXPECT_EQ(CullSettings{}.occlusion.method, OcclusionMethod::Auto);
    Scene city(scenes::buildCity({100, true}));
    city.update();
    const Picks orbit = picks(city, scenes::kOrbitFrames, 8, [](int f) { return scenes::cityOrbitCamera(100, f); });
    EXPECT_GT(3 * orbit.map, 2 * orbit.frames) << orbit.map << " of " << orbit.frames;
    // The map draws far fewer here: Auto follows it (0.64 of the tree's since the tree takes near and large
    // occluders first, which made the tree itself better over the roofs).
    EXPECT_LT(orbit.autoGeoms, 0.7 * orbit.treeGeoms);
    const Picks street = picks(city, scenes::kStreetFrames, 8, [](int f) { return scenes::cityStreetCamera(100, f); });
    EXPECT_LT(4 * street.map, street.frames) << street.map << " of " << street.frames;

    Scene office(scenes::buildOffice(8));
    office.update();
    const Picks walk = picks(office, scenes::kWalkFrames, 8, [](int f) { return scenes::officeWalkCamera(8, f); });
    EXPECT_LT(4 * walk.map, walk.frames) << walk.map << " of " << walk.frames;
    EXPECT_LE(walk.autoGeoms, walk.treeGeoms * 1.05);  // the tree, or the map where it does as well (1.03)
}

TEST(OcclusionAuto, IsExactOnTheCityFromAboveAndInItsStreets) {
    const int n = 24;
    Scene s(scenes::buildCity({n, true}));
    s.update();
    accuracy::Harness h(256, 144);
    CullSettings set;
    set.occlusion.mode = OcclusionMode::EveryFrame;
    const accuracy::Result r = h.run(s, accuracy::cityOcclusionViews(n, testutil::scaled(60), 31, 256, 144), {set})[0];
    EXPECT_EQ(r.differingTotal, 0u) << "worst view " << r.worstView;
    EXPECT_GT(r.culledOcclusionTotal, 0u);
}
