// CullSettings::validate(): every setting out of its range is refused by name, with its value and what is allowed,
// at every entry point that takes the settings; the defaults pass.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/cull/CullTraversal.h"
#include "sg/cull/OcclusionMap.h"
#include "sg/cull/OcclusionPass.h"
#include "sg/cull/OcclusionTree.h"
#include "sg/lod/DrawCostModel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

namespace {

using namespace sg;

const double kNaN = std::nan(""), kInf = std::numeric_limits<double>::infinity();

struct Bad {
    const char* setting;
    std::function<void(CullSettings&)> set;
};

// The error `validate` throws for `s`, or an empty one when it passes.
std::string errorOf(const CullSettings& s, std::string* setting = nullptr) {
    try {
        s.validate("Test::entry()");
    } catch (const SettingError& e) {
        if (setting) *setting = e.setting();
        return e.what();
    }
    return {};
}

TEST(CullSettings, TheDefaultsAreValid) {
    EXPECT_EQ(errorOf(CullSettings{}), "");
    CullSettings s;
    DrawCostModel model;
    s.lodBudget.enabled = true;
    s.lodBudget.model = &model;
    EXPECT_EQ(errorOf(s), "");
}

TEST(CullSettings, EveryBadValueIsRefusedByNameWithItsValueAndRange) {
    static DrawCostModel model;
    auto budget = [](CullSettings& s) {
        s.lodBudget.enabled = true;
        s.lodBudget.model = &model;
    };
    const Bad bad[] = {
        {"strategy", [](CullSettings& s) { s.strategy = CullStrategy(9); }},
        {"smallFeaturePixels", [](CullSettings& s) { s.smallFeaturePixels = -1.0; }},
        {"smallFeaturePixels", [](CullSettings& s) { s.smallFeaturePixels = kNaN; }},
        {"lodHysteresis", [](CullSettings& s) { s.lodHysteresis = 1.0; }},
        {"lodHysteresis", [](CullSettings& s) { s.lodHysteresis = -0.1; }},
        {"lodScale", [](CullSettings& s) { s.lodScale = 0.0; }},
        {"lodScale", [](CullSettings& s) { s.lodScale = kInf; }},
        {"screenRectTriangles", [](CullSettings& s) { s.screenRectTriangles = 0; }},
        {"screenRectTriangles", [](CullSettings& s) { s.screenRectTriangles = 65537; }},
        {"measureOnly.frustumPlanes", [](CullSettings& s) { s.measureOnly.frustumPlanes = 0x40; }},
        {"occlusion.mode", [](CullSettings& s) { s.occlusion.mode = OcclusionMode(7); }},
        {"occlusion.method", [](CullSettings& s) { s.occlusion.method = OcclusionMethod(7); }},
        {"occlusion.autoMapShare", [](CullSettings& s) { s.occlusion.autoMapShare = 1.5; }},
        {"occlusion.minOccluderPixels", [](CullSettings& s) { s.occlusion.minOccluderPixels = -2.0; }},
        {"occlusion.adaptiveMinGain", [](CullSettings& s) { s.occlusion.adaptiveMinGain = kNaN; }},
        {"occlusion.homWidth", [](CullSettings& s) { s.occlusion.homWidth = 100; }},
        {"occlusion.homHeight", [](CullSettings& s) { s.occlusion.homHeight = 2048; }},
        {"occlusion.homOpacity", [](CullSettings& s) { s.occlusion.homOpacity = 0.0; }},
        {"occlusion.homObbLevels", [](CullSettings& s) { s.occlusion.homObbLevels = 17; }},
        {"occlusion.measureOnly.cap", [](CullSettings& s) { s.occlusion.measureOnly.cap = OccluderCap(5); }},
        {"occlusion.measureOnly.screenSplits", [](CullSettings& s) { s.occlusion.measureOnly.screenSplits = 9; }},
        {"lodBudget.model",
         [](CullSettings& s) {
             s.lodBudget.enabled = true;
             s.lodBudget.model = nullptr;
         }},
        {"lodBudget.budgetMs",
         [&](CullSettings& s) {
             budget(s);
             s.lodBudget.budgetMs = 0.0;
         }},
        {"lodBudget.hysteresis",
         [&](CullSettings& s) {
             budget(s);
             s.lodBudget.hysteresis = kNaN;
         }},
        {"lodBudget.coarsestScale",
         [&](CullSettings& s) {
             budget(s);
             s.lodBudget.coarsestScale = -1.0;
         }},
        {"lodBudget.finestScale",
         [&](CullSettings& s) {
             budget(s);
             s.lodBudget.finestScale = kInf;
         }},
        {"lodBudget.overrunShare",
         [&](CullSettings& s) {
             budget(s);
             s.lodBudget.overrunShare = -0.1;
         }},
        {"lodBudget.overrunWorth",
         [&](CullSettings& s) {
             budget(s);
             s.lodBudget.overrunWorth = kNaN;
         }},
    };
    for (const Bad& b : bad) {
        CullSettings s;
        b.set(s);
        std::string setting;
        const std::string what = errorOf(s, &setting);
        EXPECT_EQ(setting, b.setting) << what;
        EXPECT_EQ(what.rfind(std::string("Test::entry(): ") + b.setting + " ", 0), 0u) << what;
        EXPECT_NE(what.find(" is not "), std::string::npos) << what;
    }
    // The budget's values are not checked while it is off.
    CullSettings off;
    off.lodBudget.budgetMs = -1.0;
    EXPECT_EQ(errorOf(off), "");
}

TEST(CullSettings, TheMessageSaysTheValueAndTheRange) {
    CullSettings s;
    s.lodHysteresis = 1.5;
    EXPECT_EQ(errorOf(s), "Test::entry(): lodHysteresis 1.5 is not in [0, 1)");
    s = CullSettings{};
    s.occlusion.homWidth = 100;
    EXPECT_EQ(errorOf(s), "Test::entry(): occlusion.homWidth 100 is not a power of two in 8..1024");
}

// Every entry point that takes the settings checks them: a bad value is refused by name there.
TEST(CullSettings, EveryEntryPointChecksThem) {
    auto root = make<Group>();
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-1.0), dvec3(1.0)), make<Material>()));
    Scene scene(root);
    scene.update();
    Camera cam;
    cam.setViewport(64, 64);
    cam.setPerspective(60.0, 1.0, 0.1, 100.0);
    cam.setLookAt(dvec3(0, -5, 0), dvec3(0.0), dvec3(0, 0, 1));
    CullSettings bad;
    bad.occlusion.measureOnly.screenSplits = -1;  // once clamped silently
    auto refusedBy = [&](const char* fn, const std::function<void()>& call) {
        try {
            call();
            ADD_FAILURE() << fn << " accepted screenSplits -1";
        } catch (const SettingError& e) {
            EXPECT_EQ(std::string(e.what()).rfind(std::string(fn) + ": occlusion.measureOnly.screenSplits -1", 0), 0u)
                << e.what();
        }
    };
    CullTraversal cull;
    DrawList list;
    CullStats stats;
    cull.cull(scene, cam, CullSettings{}, list, stats);
    ASSERT_EQ(list.items.size(), 1u);
    refusedBy("CullTraversal::cull()", [&] { cull.cull(scene, cam, bad, list, stats); });
    OcclusionPass pass;
    refusedBy("OcclusionPass::build()", [&] { pass.build(scene.image(), cam, bad, stats); });
    refusedBy("OcclusionTree::optionsFor()", [&] { OcclusionTree::optionsFor(cam, bad.occlusion); });
    refusedBy("OcclusionMap::optionsFor()", [&] { OcclusionMap::optionsFor(cam, bad.occlusion); });
    // The cull checks before it touches its output: the last frame's list is still there.
    EXPECT_EQ(list.items.size(), 1u);
}

}  // namespace

TEST(CullSettings, OcclusionModeAndMethodNamesRoundTripAndNeverMeet) {
    for (auto m : {OcclusionMode::Off, OcclusionMode::EveryFrame, OcclusionMode::Adaptive}) {
        EXPECT_EQ(parseOcclusionMode(occlusionModeName(m)), m);
        for (auto k : {OcclusionMethod::Tree, OcclusionMethod::Hom, OcclusionMethod::Auto})
            EXPECT_STRNE(occlusionModeName(m), occlusionMethodName(k));
    }
    for (auto k : {OcclusionMethod::Tree, OcclusionMethod::Hom, OcclusionMethod::Auto})
        EXPECT_EQ(parseOcclusionMethod(occlusionMethodName(k)), k);
    // The modes' older names, which scripts may still pass.
    EXPECT_EQ(parseOcclusionMode("tree"), OcclusionMode::EveryFrame);
    EXPECT_EQ(parseOcclusionMode("auto"), OcclusionMode::Adaptive);
    try {
        parseOcclusionMode("sometimes");
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(),
                     "parseOcclusionMode(): 'sometimes' is not an occlusion mode (off, every-frame, adaptive)");
    }
}

// Every enumeration a program reads by name: the names read back, and an unknown one named in one wording.
TEST(CullSettings, EveryEnumerationsNamesReadBackAndAnUnknownNameIsRefusedInOneWording) {
    for (auto s : {CullStrategy::None, CullStrategy::Sphere, CullStrategy::Aabb, CullStrategy::SphereSphere,
                   CullStrategy::CenterBox})
        EXPECT_EQ(parseStrategy(strategyName(s)), s);
    auto message = [](auto parse) {
        try {
            parse();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    EXPECT_EQ(message([] { parseStrategy("fast"); }),
              "parseStrategy(): 'fast' is not a cull strategy (none, sphere, aabb, sphere-sphere, center-box)");
    EXPECT_EQ(message([] { parseOcclusionMethod("fast"); }),
              "parseOcclusionMethod(): 'fast' is not an occlusion method (tree, hom, auto)");
    EXPECT_EQ(message([] { parseStrategy(""); }),
              "parseStrategy(): '' is not a cull strategy (none, sphere, aabb, sphere-sphere, center-box)");
}
