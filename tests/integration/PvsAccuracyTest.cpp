// The PVS pre-pass draws exactly the pixels of the unculled render, alone and with the occlusion tree, on
// city's streets and office's rooms, the eye anywhere in a cell (random points, cell corners and faces);
// and it is not vacuous: it culled entries on most views.
#include "Scaled.h"
#include "sg/build/PvsBuilder.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Office.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 144, kViewsPerScene = testutil::scaled(100);

// Eyes in the table's computed cells: a third at cell corners, a third on cell faces, a third inside.
std::vector<Camera> viewsInCells(const PvsTable& t, int count, double zNear, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<Camera> views;
    for (int v = 0; v < count; ++v) {
        const Box b = t.cellBox(size_t(rng() % t.cellCount()));
        dvec3 f(u01(rng), u01(rng), u01(rng));
        if (v % 3 == 0) f = glm::floor(f + 0.5);  // a corner
        if (v % 3 == 1) f[int(rng() % 3)] = double(rng() % 2);
        const dvec3 eye = b.min + f * (b.max - b.min);
        const double yaw = 2.0 * M_PI * u01(rng), pitch = 0.6 * (u01(rng) - 0.5);
        const dvec3 dir(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch));
        Camera cam;
        cam.setViewport(kW, kH);
        cam.setPerspective(v % 4 == 3 ? 90.0 : 60.0, double(kW) / kH, zNear, 3000.0);
        cam.setLookAt(eye, eye + dir, dvec3(0, 0, 1));
        views.push_back(cam);
    }
    return views;
}

void checkExact(const Scene& s, const PvsTable& t, const std::vector<Camera>& views, const char* name) {
    accuracy::Harness h(kW, kH);
    CullSettings pvs;
    pvs.pvs = &t;
    pvs.occlusion.mode = OcclusionMode::Off;
    CullSettings both = pvs;
    both.occlusion.mode = OcclusionMode::EveryFrame;
    both.occlusion.method = OcclusionMethod::Tree;
    CullSettings frustum = pvs;
    frustum.pvs = nullptr;
    for (const auto& [set, label] : {std::pair{&pvs, "pvs"}, std::pair{&both, "pvs+tree"}}) {
        uint64_t differing = 0, culled = 0, tris = 0, trisFrustum = 0;
        int viewsCulling = 0;
        for (size_t v = 0; v < views.size(); ++v) {
            CullStats st, sf;
            const uint64_t d = h.compare(s, views[v], *set, nullptr, nullptr, &st);
            EXPECT_EQ(d, 0u) << name << " " << label << " view " << v << ": " << accuracy::describeCamera(views[v])
                             << " (" << st.culledPvs << " entries culled by the PVS)";
            h.compare(s, views[v], frustum, nullptr, nullptr, &sf);
            differing += d;
            culled += st.culledPvs;
            viewsCulling += st.culledPvs > 0;
            tris += st.triangles;
            trisFrustum += sf.triangles;
        }
        std::printf(
            "[ accuracy ] %-8s %-10s views %zu  differing pixels %llu  culled by the PVS %llu (in %d views)"
            "  triangles drawn %llu, frustum alone %llu\n",
            name, label, views.size(), (unsigned long long)differing, (unsigned long long)culled, viewsCulling,
            (unsigned long long)tris, (unsigned long long)trisFrustum);
        EXPECT_GT(viewsCulling, int(views.size()) / 2) << name << " " << label << ": the PVS culled too rarely";
        EXPECT_LT(tris, trisFrustum) << name << " " << label;
    }
}
}  // namespace

TEST(PvsAccuracy, CityStreetsAreExact) {
    const int n = 14;
    Scene s(scenes::buildCity({n, true}));
    s.update();
    // The street at x = 140 (between buildings at x <= 136 and >= 144), the whole city's length, at eye height.
    PvsBuilder::Options o;
    o.region = Box{dvec3(138, 0, 1.2), dvec3(142, 280, 2.2)};
    o.cellSize = dvec3(5, 10, 1);
    o.minNear = 0.5;
    const PvsTable t = PvsBuilder::build(s, o);
    checkExact(s, t, viewsInCells(t, kViewsPerScene, 0.5, 11), "city");
}

TEST(PvsAccuracy, OfficeRoomsAreExact) {
    const int r = 6;
    Scene s(scenes::buildOffice(r));
    s.update();
    // The walk's corridor through the doors of the middle row of rooms (y = 21), at eye height; and one room,
    // with only the projection plane just beyond the largest occluder (the others draw both planes).
    PvsBuilder::Options o;
    o.region = Box{dvec3(0.5, 20.6, 1.2), dvec3(35.5, 21.4, 2.0)};
    o.cellSize = dvec3(1, 1, 1);
    o.minNear = 0.1;
    const PvsTable walk = PvsBuilder::build(s, o);
    checkExact(s, walk, viewsInCells(walk, kViewsPerScene / 2, 0.1, 12), "office");
    o.region = Box{dvec3(13, 13, 1.2), dvec3(17, 17, 1.8)};  // inside room (2, 2), away from its walls
    o.cellSize = dvec3(2, 2, 1);
    o.plane = PvsBuilder::Plane::BeyondLargest;
    const PvsTable room = PvsBuilder::build(s, o);
    checkExact(s, room, viewsInCells(room, kViewsPerScene / 2, 0.1, 13), "office");
}
