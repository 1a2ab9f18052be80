// Occluders made from the geometry (sg/build/GeneratedOccluders.h) keep the occlusion pass conservative: the city,
// the office, the factory and a city read back from glTF, with their authored occluders removed and occluders generated
// instead, draw exactly the pixels of the unculled render on every view, with the tree and with the map, and cull
// about as much as the authored ones do on the same views; open meshes boxed with their openings capped are exact from
// every side, seen through their openings too.
#include "Scaled.h"
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/build/GeneratedOccluders.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/FactoryWalk.h"
#include "testbed/Office.h"
#include "testbed/Rng.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 144;
const int kViews = testutil::scaled(120);

CullSettings pass(OcclusionMethod m) {
    CullSettings c;
    c.occlusion.mode = OcclusionMode::EveryFrame;
    c.occlusion.method = m;
    return c;
}
const std::vector<CullSettings> kMethods = {pass(OcclusionMethod::Tree), pass(OcclusionMethod::Hom)};

ref_ptr<Node> generated(ref_ptr<Node> root) {
    removeOccluders(*root);
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_GT(st.boxes + st.polygons, 0u);
    return root;
}

// Each method on the scene with generated occluders: no differing pixel, something culled, and at most `ratio` times
// the triangles the same method draws with the authored occluders.
void compare(const Scene& authored, const Scene& made, const std::vector<Camera>& views, const char* name,
             double ratio) {
    accuracy::Harness h(kW, kH);
    const std::vector<accuracy::Result> a = h.run(authored, views, kMethods), g = h.run(made, views, kMethods);
    for (size_t k = 0; k < kMethods.size(); ++k) {
        std::printf("[ generated ] %-8s %-20s triangles %llu (authored %llu), culled %llu, differing pixels %llu\n",
                    name, g[k].name.c_str(), (unsigned long long)g[k].trianglesTotal,
                    (unsigned long long)a[k].trianglesTotal, (unsigned long long)g[k].culledOcclusionTotal,
                    (unsigned long long)g[k].differingTotal);
        EXPECT_EQ(g[k].differingTotal, 0u) << name << " " << g[k].name << ": worst view " << g[k].worstView;
        EXPECT_GT(g[k].culledOcclusionTotal, 0u) << name << " " << g[k].name;
        EXPECT_LE(double(g[k].trianglesTotal), ratio * double(a[k].trianglesTotal)) << name << " " << g[k].name;
    }
}
}  // namespace

TEST(GeneratedOccludersAccuracy, CityIsExactAndCullsAsMuchAsItsAuthoredBoxes) {
    // Street-level and aerial views, the eye in a building's face plane and close to walls among them.
    const int n = 14;
    Scene authored(scenes::buildCity({n, true})), made(generated(scenes::buildCity({n, true})));
    authored.update();
    made.update();
    compare(authored, made, accuracy::cityOcclusionViews(n, kViews, 2025, kW, kH), "city", 1.15);
}

TEST(GeneratedOccludersAccuracy, OfficeIsExactAndCullsAsMuchAsItsAuthoredWalls) {
    // Furniture makes occluders too; the walls must still be the ones the pass takes.
    const int r = 6;
    Scene authored(scenes::buildOffice(r)), made(generated(scenes::buildOffice(r)));
    authored.update();
    made.update();
    compare(authored, made, accuracy::officeViews(r, kViews, 77, kW, kH), "office", 1.15);
}

TEST(GeneratedOccludersAccuracy, FactoryPathIsExact) {
    // The walkthrough's path, each view with the Switch state of its eye: occluders below the outside Switch (the
    // buildings' walls, LOD'd) are used only while it shows them.
    scenes::Factory site = scenes::buildFactory();
    generated(site.root);
    Scene scene(site.root);
    scene.update();
    const scenes::WalkPath walk = scenes::buildWalkPath(site, scene, 240);
    accuracy::Harness h(kW, kH);
    uint64_t differing = 0, culled = 0;
    int shown = -2;
    const size_t step = size_t(240 / testutil::scaled(40));
    for (size_t f = 0; f < walk.frames.size(); f += step) {
        if (walk.frames[f].workshop != shown) {
            scenes::setFactoryEye(site, shown = walk.frames[f].workshop);
            scene.update();
        }
        for (const CullSettings& s : kMethods) {
            CullStats st;
            const uint64_t d = h.compare(scene, scenes::pathCamera(walk.frames[f], kW, kH), s, nullptr, nullptr, &st);
            EXPECT_EQ(d, 0u) << "frame " << f << " " << accuracy::settingName(s);
            differing += d;
            culled += st.culledOcclusion;
        }
    }
    std::printf("[ generated ] factory path: culled %llu, differing pixels %llu\n", (unsigned long long)culled,
                (unsigned long long)differing);
    EXPECT_GT(culled, 0u);
}

TEST(GeneratedOccludersAccuracy, CityReadFromGltfIsExact) {
    // The city written as glTF (turned to +Y up, as sgview --save does) and read back with occluders generated at
    // load (GltfLoadOptions::generateOccluders), turned back to +Z up for the views.
    const int n = 8;
    auto yUp = make<Transform>(glm::rotate(dmat4(1.0), -glm::half_pi<double>(), dvec3(1, 0, 0)));
    yUp->addChild(scenes::buildCity({n, false}));
    const std::string file = (std::filesystem::temp_directory_path() / "sg_generated_occluders_city.glb").string();
    saveGltf(*yUp, file);
    GltfLoadOptions o;
    o.generateOccluders = true;
    auto zUp = make<Transform>(glm::rotate(dmat4(1.0), glm::half_pi<double>(), dvec3(1, 0, 0)));
    zUp->addChild(loadGltf(file, o).root);
    std::filesystem::remove(file);
    Scene authored(scenes::buildCity({n, true})), made(zUp);
    authored.update();
    made.update();
    EXPECT_GE(made.image().occluders.size(), size_t(n * n));
    compare(authored, made, accuracy::cityOcclusionViews(n, kViews, 7, kW, kH), "gltf city", 1.15);
}

namespace {
// Four walls about the x axis from x0 to x1 (a w x w section from z0), counter-clockwise seen from outside; no ends.
ref_ptr<Mesh> wallsAlongX(double x0, double x1, double w, double z0) {
    const double y = w / 2;
    std::vector<vec3> pos;
    std::vector<uint32_t> idx;
    const dvec2 c[4] = {{-y, z0}, {y, z0}, {y, z0 + w}, {-y, z0 + w}};  // (y, z) round the section
    for (int k = 0; k < 4; ++k) {
        const dvec2 a = c[k], b = c[(k + 1) % 4];
        const uint32_t base = uint32_t(pos.size());
        pos.push_back(vec3(dvec3(x0, a.x, a.y)));
        pos.push_back(vec3(dvec3(x1, a.x, a.y)));
        pos.push_back(vec3(dvec3(x1, b.x, b.y)));
        pos.push_back(vec3(dvec3(x0, b.x, b.y)));
        // Seen from outside the section, x0 -> x1 -> along the section turns counter-clockwise.
        idx.insert(idx.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    }
    auto m = make<Mesh>();
    m->set(std::move(pos), std::vector<vec3>(16, vec3(0, 0, 1)), std::move(idx), std::vector<vec2>(16, vec2(0.0f)));
    return m;
}
}  // namespace

TEST(GeneratedOccludersAccuracy, OpenMeshesAreExactSeenThroughTheirOpenings) {
    // Tubes open at both ends raised on the ground, and floorless buildings (walls and a roof), with boxes beyond the
    // tubes' ends (seen through them along the axis) and behind everything. Generated boxes fill each tube and
    // building; seen through an opening, the eye is on the far side of its plane and the box must not be used.
    auto root = make<Group>();
    auto mat = make<Material>();
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-200, -200, -1), dvec3(200, 200, 0)), mat));
    for (int k = 0; k < 3; ++k) {
        const double y = -30.0 + 30.0 * k;
        auto tube = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, y, 0)));
        tube->addChild(make<Geometry>(wallsAlongX(-10, 10, 6, 2), mat));
        root->addChild(tube);
        for (double x : {-30.0, 30.0})
            root->addChild(make<Geometry>(makeBoxMesh(dvec3(x - 1, y - 1, 4), dvec3(x + 1, y + 1, 6)), mat));
        // A floorless building beside it: walls about the vertical axis and a closed roof slab.
        auto building = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, y + 12, 0)) *
                                        glm::rotate(dmat4(1.0), glm::half_pi<double>(), dvec3(0, -1, 0)));
        building->addChild(make<Geometry>(wallsAlongX(0, 8, 6, -3), mat));  // x 0..8 becomes z 0..8
        root->addChild(building);
        root->addChild(make<Geometry>(makeBoxMesh(dvec3(-3, y + 9, 8), dvec3(3, y + 15, 8.5)), mat));
        root->addChild(make<Geometry>(makeBoxMesh(dvec3(-1, y + 30, 0), dvec3(1, y + 32, 3)), mat));
    }
    // The ground's box would make every tube and building minor (OccluderGenSettings::minMajorShare): all are kept.
    OccluderGenSettings gs;
    gs.minMajorShare = 0.0;
    const OccluderGenStats st = generateOccluders(*root, gs);
    EXPECT_GE(st.boxes, 7u) << "a box in the ground, every tube and building";
    Scene scene(root);
    scene.update();
    size_t withOpenings = 0;
    for (const FlatImage::OccluderRef& o : scene.image().occluders)
        withOpenings += !static_cast<const Occluder*>(o.node)->openings().empty();
    EXPECT_GE(withOpenings, 6u);

    // Along each tube's axis from beyond either end (eye in the opening's plane among them), from the street, and
    // from above.
    std::vector<Camera> views;
    auto view = [&](const dvec3& eye, const dvec3& at) {
        Camera c;
        c.setViewport(kW, kH);
        c.setPerspective(50.0, double(kW) / kH, 0.1, 1000.0);
        c.setLookAt(eye, at, glm::abs(glm::normalize(at - eye).z) > 0.99 ? dvec3(0, 1, 0) : dvec3(0, 0, 1));
        views.push_back(c);
    };
    scenes::Rng rng(41);
    for (int k = 0; k < 3; ++k) {
        const double y = -30.0 + 30.0 * k;
        for (double x : {-10.0, -12.0, -25.0, 10.0, 14.0})
            view(dvec3(x, y + rng.uniform(-0.5, 0.5), 5), dvec3(-x, y, 5));
        view(dvec3(0, y - 25, 1.7), dvec3(0, y + 40, 3));  // from the street: the tube and building hide what is behind
        view(dvec3(0, y + 12, 30), dvec3(0, y + 12, 0));   // down onto the roof
        view(dvec3(0, y + 12.5, 8), dvec3(0, y + 40, 2));  // the eye at the walls' top
    }
    for (int i = 0; i < testutil::scaled(24); ++i)
        view(dvec3(rng.uniform(-60, 60), rng.uniform(-60, 60), rng.uniform(1, 40)),
             dvec3(rng.uniform(-10, 10), rng.uniform(-30, 30), 4));
    accuracy::Harness h(kW, kH);
    for (const accuracy::Result& r : h.run(scene, views, kMethods)) {
        std::printf(
            "[ generated ] open meshes %-20s triangles %llu (unculled %llu), culled %llu, differing pixels %llu\n",
            r.name.c_str(), (unsigned long long)r.trianglesTotal, (unsigned long long)r.referenceTrianglesTotal,
            (unsigned long long)r.culledOcclusionTotal, (unsigned long long)r.differingTotal);
        EXPECT_EQ(r.differingTotal, 0u) << r.name << ": worst view " << r.worstView << " "
                                        << accuracy::describeCamera(views[size_t(std::max(r.worstView, 0))]);
        EXPECT_GT(r.culledOcclusionTotal, 0u) << r.name;
    }
}
