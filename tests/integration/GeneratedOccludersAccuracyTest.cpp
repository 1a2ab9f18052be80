// Occluders made from the geometry (sg/scene/GeneratedOccluders.h) keep the occlusion pass conservative: the city,
// the office, the factory and a city read back from glTF, with their authored occluders removed and occluders generated
// instead, draw exactly the pixels of the unculled render on every view, with the tree and with the map, and cull
// about as much as the authored ones do on the same views.
#include "Scaled.h"
#include "loaders/Gltf.h"
#include "nodes/Transform.h"
#include "sg/scene/GeneratedOccluders.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/FactoryWalk.h"
#include "testbed/Office.h"

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
