// The cull on degenerate input, every conservative method against the unculled render: zero-size bounds (a
// point, a degenerate triangle), the eye exactly in a face's plane and in an occluder's plane, occluder
// polygons with collinear vertices, the city scaled from 1e-6 to 1e6, and frusta whose planes are nearly
// parallel (fields of view of 0.01 and 179.9 degrees, narrow off-axis frusta). Nothing may be culled that
// the reference draws, and nothing the cull reports may be NaN.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/core/Material.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <string>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 144;

bool finite(const CullStats& st) {
    for (double v : {st.occlusionMs, st.lodBudgetMs, st.lodPixels, st.lodPredictedMs, st.lodSelectMs, st.ms})
        if (!std::isfinite(v)) return false;
    return true;
}

// Culls one view; the meshes drawn. Fails the test on a NaN in the stats or in a drawn item's matrix.
std::set<const Mesh*> drawn(const Scene& scene, const Camera& cam, const CullSettings& s, CullStats* out = nullptr) {
    CullTraversal cull;
    DrawList list;
    CullStats st;
    cull.cull(scene, cam, s, list, st);
    EXPECT_TRUE(finite(st)) << accuracy::settingName(s) << ": " << accuracy::describeCamera(cam);
    std::set<const Mesh*> m;
    for (const DrawItem& it : list.items) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 3; ++r) EXPECT_TRUE(std::isfinite(it.model[c][r])) << accuracy::settingName(s);
        m.insert(it.mesh);
    }
    if (out) *out = st;
    return m;
}

ref_ptr<Geometry> geometry(std::vector<vec3> pos, std::vector<uint32_t> idx) {
    auto mesh = make<Mesh>();
    const std::vector<vec3> nrm(pos.size(), vec3(0, 0, 1));
    mesh->set(std::move(pos), nrm, std::move(idx));
    return make<Geometry>(mesh, make<Material>());
}

ref_ptr<Geometry> boxGeometry(const dvec3& lo, const dvec3& hi) {
    return make<Geometry>(makeBoxMesh(lo, hi, 2), make<Material>());
}

Camera camera(const dvec3& eye, const dvec3& at, const dvec3& up, double fov = 60.0, double nearD = 0.1) {
    Camera c;
    c.setLookAt(eye, at, up);
    c.setPerspective(fov, double(kW) / kH, nearD, 500.0);
    c.setViewport(kW, kH);
    return c;
}

// Every conservative setting draws exactly the reference's pixels on every view; returns the bounds
// culled by occlusion over all (the caller checks the views were not trivially easy). With a LOD scale,
// the reference is drawn with it too.
uint64_t expectExact(accuracy::Harness& h, const Scene& scene, const std::vector<Camera>& views, const char* what,
                     double lodScale = 1.0) {
    uint64_t occlusionCulled = 0;
    for (CullSettings s : accuracy::conservativeSettings()) {
        s.lodScale = lodScale;
        uint64_t differing = 0;
        int worst = -1;
        for (size_t v = 0; v < views.size(); ++v) {
            CullStats st;
            const uint64_t d = h.compare(scene, views[v], s, nullptr, nullptr, &st);
            EXPECT_TRUE(finite(st)) << what;
            occlusionCulled += st.culledOcclusion;
            if (d > 0 && differing == 0) worst = int(v);
            differing += d;
        }
        EXPECT_EQ(differing, 0u) << what << ", " << accuracy::settingName(s) << ": first view with error " << worst
                                 << " ("
                                 << (worst >= 0 ? accuracy::describeCamera(views[size_t(worst)]) : std::string())
                                 << ")";
    }
    return occlusionCulled;
}
}  // namespace

TEST(DegenerateCull, ZeroSizeBoundsAreDrawnInViewAndCulledOutOfIt) {
    // A one-point mesh (one triangle on a single vertex) and a degenerate triangle (collinear vertices):
    // their boxes have no volume, their spheres no radius. In view they are drawn by every method (the GPU
    // draws nothing of them, so only the draw list can tell); behind the eye they are culled by the
    // frustum strategies, and one hidden behind a wall is culled by the occlusion methods.
    auto root = make<Group>();
    auto point = geometry({vec3(0, 0, -10)}, {0, 0, 0});
    auto line = geometry({vec3(2, 0, -10), vec3(3, 1, -10), vec3(4, 2, -10)}, {0, 1, 2});
    auto behind = geometry({vec3(0, 0, 10)}, {0, 0, 0});
    // On the left plane of the 90-degree view below (x = z), and a hair outside it.
    auto onPlane = geometry({vec3(-20, 0, -20)}, {0, 0, 0});
    // Not in a plane through the eye parallel to an axis: there the pass leaves a bound to be drawn (seen edge-on).
    auto hidden = geometry({vec3(0.5f, 1.5f, -40)}, {0, 0, 0});
    auto occ = make<Occluder>();
    occ->setBox(Box{dvec3(-10, -10, -31), dvec3(10, 10, -30)});
    for (auto& g : {point, line, behind, onPlane, hidden}) root->addChild(g);
    root->addChild(boxGeometry(dvec3(-10, -10, -31), dvec3(10, 10, -30)));
    root->addChild(occ);
    Scene s(root);
    s.update();
    Camera cam;
    cam.setLookAt(dvec3(0.0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    cam.setPerspective(90.0, 1.0, 0.5, 100.0);
    cam.setViewport(kW, kW);
    for (const CullSettings& set : accuracy::conservativeSettings()) {
        const std::string name = accuracy::settingName(set);
        const std::set<const Mesh*> m = drawn(s, cam, set);
        EXPECT_TRUE(m.count(point->mesh())) << name;
        EXPECT_TRUE(m.count(line->mesh())) << name;
        EXPECT_TRUE(m.count(onPlane->mesh())) << name << ": a point on a frustum plane was culled";
        EXPECT_FALSE(m.count(behind->mesh())) << name;
        if (set.occlusion.mode != OcclusionMode::Off) {
            EXPECT_FALSE(m.count(hidden->mesh())) << name;
        }
    }
}

TEST(DegenerateCull, EyeInAFacesPlaneAndInAnOccludersPlane) {
    // A box occluder, a polygon occluder and boxes behind and beside them; the eye exactly in the planes of
    // their faces (looking along a face, across it, down its edge), on an occluder's edge line, and in the
    // polygon's plane, at heights level with tops. Exact on every view, and the occluders do cull.
    auto root = make<Group>();
    auto wall = make<Occluder>();
    wall->setBox(Box{dvec3(-10, 0, -21), dvec3(10, 10, -20)});
    root->addChild(wall);
    root->addChild(boxGeometry(dvec3(-10, 0, -21), dvec3(10, 10, -20)));
    auto pane = make<Occluder>();
    pane->setPolygon({dvec3(20, 0, -30), dvec3(40, 0, -30), dvec3(40, 10, -30), dvec3(20, 10, -30)});
    root->addChild(pane);
    root->addChild(boxGeometry(dvec3(20, 0, -30), dvec3(40, 10, -30)));  // the pane's own face, flat
    for (int i = -3; i <= 3; ++i) {
        root->addChild(boxGeometry(dvec3(i * 3.0 - 1, 0, -40), dvec3(i * 3.0 + 1, 4 + i + 3, -38)));
        root->addChild(boxGeometry(dvec3(24 + i, 0, -45), dvec3(25 + i, 5, -44)));
        root->addChild(boxGeometry(dvec3(-10, 0, -20 + i * 0.5 + 0.25), dvec3(-9.5, 3, -19.75 + i * 0.5)));
    }
    root->addChild(boxGeometry(dvec3(-100, -1, -100), dvec3(100, 0, 10)));  // ground, its top at y = 0
    Scene s(root);
    s.update();
    const dvec3 up(0, 1, 0);
    std::vector<Camera> views = {
        camera(dvec3(0, 5, -20), dvec3(0, 5, -60), up),      // in the wall's back face plane, inside the wall
        camera(dvec3(0, 5, -10), dvec3(0, 5, -60), up),      // straight at the wall
        camera(dvec3(-10, 5, 0), dvec3(-10, 5, -60), up),    // in the wall's left face plane, along it
        camera(dvec3(-10, 10, 0), dvec3(-10, 10, -60), up),  // on its top-left edge's line
        camera(dvec3(0, 10, 0), dvec3(0, 10, -60), up),      // level with its top
        camera(dvec3(-30, 5, -20), dvec3(30, 5, -20), up),   // in its front face's plane, looking along it
        camera(dvec3(-30, 5, -21), dvec3(0, 5, -40), up),    // in its back face's plane, looking past it
        camera(dvec3(30, 5, -30), dvec3(30, 5, -60), up),    // in the pane's plane, on the pane
        camera(dvec3(10, 5, -30), dvec3(50, 5, -30), up),    // in the pane's plane, looking along it
        camera(dvec3(20, 5, 0), dvec3(20, 5, -60), up),      // in the plane of the pane's left edge
        camera(dvec3(30, 5, 0), dvec3(30, 5, -60), up),      // straight at the pane
        camera(dvec3(30, 0, 0), dvec3(30, 0, -60), up),      // level with the ground's top, the pane's bottom
        camera(dvec3(0, 0, 0), dvec3(0, 5, -60), up, 120.0, 0.01),
        camera(dvec3(-10, 5, -20), dvec3(10, 5, -60), up, 60.0, 1e-3),  // on the wall's edge
    };
    accuracy::Harness h(kW, kH);
    EXPECT_GT(expectExact(h, s, views, "hand-made faces"), 0u) << "the occluders culled nothing";
}

TEST(DegenerateCull, CollinearOccluderVerticesAreRefusedOrHarmless) {
    // Three collinear vertices: no area, no plane. Refused by Occluder::setPolygon; if ever accepted, the
    // occluder must not cull. A quad with a fourth vertex in the middle of an edge is a valid polygon (two
    // edges on one line): it culls what it hides and nothing else.
    Occluder line;
    EXPECT_THROW(line.setPolygon({dvec3(0, 0, -10), dvec3(1, 1, -10), dvec3(2, 2, -10)}), std::invalid_argument);
    EXPECT_THROW(line.setPolygon({dvec3(1e6 + 0.1, 3, 7), dvec3(1e6 + 0.2, 3.1, 7.1), dvec3(1e6 + 0.3, 3.2, 7.2)}),
                 std::invalid_argument);
    for (bool far : {false, true}) {
        const dvec3 o = far ? dvec3(1e6 + 0.1, 3.0, 7.0) : dvec3(0.0);
        auto root = make<Group>();
        auto thin = make<Occluder>();
        // Nearly collinear: 1e-9 off the line, over 20 m (accepted or not, it must not cull what it does not hide).
        bool accepted = true;
        try {
            thin->setPolygon({o + dvec3(-10, 1, -20), o + dvec3(0, 1 + 1e-9, -20), o + dvec3(10, 1, -20)});
        } catch (const std::invalid_argument&) {
            accepted = false;
        }
        if (accepted) root->addChild(thin);
        auto quad = make<Occluder>();
        quad->setPolygon({o + dvec3(-5, 2, -25), o + dvec3(0, 2, -25), o + dvec3(5, 2, -25), o + dvec3(5, 8, -25),
                          o + dvec3(-5, 8, -25)});
        root->addChild(quad);
        root->addChild(boxGeometry(o + dvec3(-5, 2, -25.01), o + dvec3(5, 8, -25)));
        for (int i = -4; i <= 4; ++i)
            for (int j = 0; j < 3; ++j)
                root->addChild(boxGeometry(o + dvec3(i * 2.5 - 0.5, j * 3.0, -40 - j),
                                           o + dvec3(i * 2.5 + 0.5, j * 3.0 + 1, -39 - j)));
        Scene s(root);
        s.update();
        std::vector<Camera> views;
        for (int k = 0; k < 12; ++k) {
            const dvec3 eye = o + dvec3(-6 + k, 1 + 0.6 * k, 0);
            views.push_back(camera(eye, o + dvec3(0, 4, -40), dvec3(0, 1, 0)));
        }
        views.push_back(camera(o + dvec3(0, 1, 0), o + dvec3(0, 1, -40), dvec3(0, 1, 0)));  // in the thin one's plane
        views.push_back(camera(o + dvec3(0, 2, 0), o + dvec3(0, 2, -40), dvec3(0, 1, 0)));  // on the quad's long edge
        accuracy::Harness h(kW, kH);
        EXPECT_GT(expectExact(h, s, views, far ? "collinear vertices, far" : "collinear vertices"), 0u)
            << "the quad culled nothing";
    }
}

TEST(DegenerateCull, CityScaledFrom1eMinus6To1e6IsExact) {
    // The city under a Transform scaling it by k, and the camera with it (its eye and near and far planes
    // times k): the same pictures at every scale. Every conservative method draws exactly the unculled render.
    const int n = 8;
    const std::vector<Camera> base = accuracy::cityOcclusionViews(n, 12, 41, kW, kH);
    accuracy::Harness h(kW, kH);
    for (double k : {1e-6, 1e-3, 1.0, 1e3, 1e6}) {
        auto top = make<Transform>(glm::scale(dmat4(1.0), dvec3(k)));
        top->addChild(scenes::buildCity({n, true}));
        Scene s(top);
        s.update();
        std::vector<Camera> views;
        for (Camera c : base) {
            dmat4 v = c.view();
            v[3] = dvec4(dvec3(v[3]) * k, 1.0);
            dmat4 p = c.projection();
            p[3][2] *= k;  // near and far times k: the same depths in clip space
            c.setView(v);
            c.setProjection(p);
            views.push_back(c);
        }
        // LOD distances are measured in world units: the LOD scale 1 / k keeps city's levels (and so the
        // pictures) those of scale 1. Without it, at 100 and more the buildings' LODs draw nothing while
        // their occluders, siblings of the LODs, still occlude, and the occlusion methods cull what the
        // reference shows: the scene's occluders no longer stand for what is drawn.
        const std::string what = "city scaled by " + std::to_string(k);
        EXPECT_GT(expectExact(h, s, views, what.c_str(), 1.0 / k), 0u) << what << ": occlusion culled nothing";
    }
}

TEST(DegenerateCull, NearlyParallelFrustumPlanes) {
    // Fields of view of 0.01 and 179.9 degrees, and off-axis frusta 1e-4 of the near distance wide, far to
    // the side: planes that meet at grazing angles. No NaN in the stats or the draw list, exact pictures.
    const int n = 8;
    Scene s(scenes::buildCity({n, true}));
    s.update();
    accuracy::Harness h(kW, kH);
    for (double fov : {0.01, 179.9}) {
        std::vector<Camera> views;
        for (const Camera& base : accuracy::cityOcclusionViews(n, 12, 43, kW, kH)) {
            Camera c = base;
            c.setPerspective(fov, double(kW) / kH, base.nearDistance(), 3000.0);
            views.push_back(c);
        }
        uint64_t frustumCulled = 0;
        for (const Camera& c : views) {
            CullStats st;
            drawn(s, c, accuracy::conservativeSettings()[1], &st);
            frustumCulled += st.culledFrustum;
        }
        EXPECT_GT(frustumCulled, 0u) << "fov " << fov;
        expectExact(h, s, views, ("fov " + std::to_string(fov)).c_str());
    }
    std::vector<Camera> views;
    for (const Camera& base : accuracy::cityOcclusionViews(n, 12, 47, kW, kH)) {
        const double nearD = base.nearDistance();
        for (double side : {0.0, 3.0}) {
            Camera c = base;
            const double l = side * nearD, w = 1e-4 * nearD;
            c.setProjection(glm::frustum(l, l + w, -0.5 * w, 0.5 * w, nearD, 3000.0));
            views.push_back(c);
        }
    }
    for (const Camera& c : views) drawn(s, c, accuracy::conservativeSettings()[4]);
    expectExact(h, s, views, "narrow off-axis frusta");
}
