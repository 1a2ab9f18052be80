// LOD fade (LOD::setTransition): which children the cull emits in a band, with which dissolve shares.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "sg/cull/CullTraversal.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace sg;

namespace {

// Child 0 detailed over [0, 100), child 1 coarse over [100, 1000), a 20 m band; the eye on the x axis.
struct FadedLod {
    ref_ptr<Geometry> detailed = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1), 4), make<Material>());
    ref_ptr<Geometry> coarse = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>());
    ref_ptr<LOD> lod = make<LOD>();
    FadedLod() {
        lod->addChild(detailed, 0, 100);
        lod->addChild(coarse, 100, 1000);
        lod->setCenter(dvec3(0.0));
        lod->setTransition(20.0f);
    }
};

Camera cameraAt(double x) {
    Camera cam;
    cam.setViewport(200, 200);
    cam.setPerspective(60.0, 1.0, 1.0, 3000.0);
    cam.setLookAt(dvec3(x, 0, 0), dvec3(0, 0, 0), dvec3(0, 0, 1));
    return cam;
}

// Share of the pixels each mesh covers (1: opaque) as the cull emits them.
std::map<const Mesh*, float> shares(const Scene& s, double x, CullSettings set = {}) {
    DrawList l;
    CullStats st;
    CullTraversal().cull(s, cameraAt(x), set, l, st);
    std::map<const Mesh*, float> out;
    for (const DrawItem& it : l.items) out[it.mesh] = 1.0f;
    for (auto [i, f] : l.fades) out[l.items[i].mesh] = f > 0.0f ? f : -f;
    return out;
}

}  // namespace

TEST(LodFade, ChildrenDissolveIntoEachOtherAcrossTheBand) {
    FadedLod f;
    Scene s(f.lod);
    s.update();
    const Mesh *d = f.detailed->mesh(), *c = f.coarse->mesh();
    // Outside the band: one child, opaque.
    EXPECT_EQ(shares(s, 80.0), (std::map<const Mesh*, float>{{d, 1.0f}}));
    EXPECT_EQ(shares(s, 120.0), (std::map<const Mesh*, float>{{c, 1.0f}}));
    // In the band: both, with shares that add up to exactly 1, the detailed one fading as the eye leaves.
    float last = 1.0f;
    for (double x = 90.5; x < 110.0; x += 1.0) {
        DrawList l;
        CullStats st;
        CullTraversal().cull(s, cameraAt(x), CullSettings{}, l, st);
        ASSERT_EQ(l.items.size(), 2u) << x;
        ASSERT_EQ(l.fades.size(), 2u) << x;
        float out = 0.0f, in = 0.0f;
        for (auto [i, v] : l.fades) (l.items[i].mesh == d ? out : in) = v;
        // The fading-out child keeps pattern < out, the fading-in one pattern >= 1 + in: complementary.
        EXPECT_GT(out, 0.0f) << x;
        EXPECT_LT(in, 0.0f) << x;
        EXPECT_EQ(out, 1.0f + in) << x;
        EXPECT_NEAR(out, (110.0 - x) / 20.0, 1.0 / 4096.0) << x;
        EXPECT_LT(out, last);
        last = out;
    }
    // The far end of the last range fades out to nothing over the band too.
    const auto far = shares(s, 1005.0);
    ASSERT_EQ(far.size(), 1u);
    EXPECT_NEAR(far.at(c), 0.25f, 1.0 / 4096.0);
    EXPECT_TRUE(shares(s, 1011.0).empty());
}

TEST(LodFade, OffMeansThePlainBoundariesAndItOverridesHysteresis) {
    FadedLod f;
    Scene s(f.lod);
    s.update();
    CullSettings off;
    off.lodFade = false;
    EXPECT_EQ(shares(s, 99.0, off), (std::map<const Mesh*, float>{{f.detailed->mesh(), 1.0f}}));
    EXPECT_EQ(shares(s, 101.0, off), (std::map<const Mesh*, float>{{f.coarse->mesh(), 1.0f}}));
    // With hysteresis as well, the band still decides (both children in it).
    CullSettings both;
    both.lodHysteresis = 0.05;
    EXPECT_EQ(shares(s, 101.0, both).size(), 2u);
    // The LOD under a Group, reached by the walk's fast path for subtrees inside the frustum, fades as well.
    auto root = make<Group>();
    root->addChild(f.lod);
    Scene s2(root);
    s2.update();
    EXPECT_EQ(shares(s2, 100.0).size(), 2u);
}

TEST(LodFade, BadWidthIsRefusedByName) {
    auto lod = make<LOD>();
    EXPECT_THROW(lod->setTransition(-1.0f), std::invalid_argument);
    EXPECT_THROW(lod->setTransition(std::nanf("")), std::invalid_argument);
    try {
        lod->setTransition(INFINITY);
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("LOD::setTransition()"), std::string::npos);
    }
    EXPECT_EQ(lod->transition(), 0.0f);
}
