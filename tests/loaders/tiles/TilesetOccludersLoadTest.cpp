// TilesetOptions::generateOccluders without a renderer (in sg_thread_tests, which CI also runs under ThreadSanitizer):
// loads on two loader threads make their tiles' occluders, sharing meshes between tiles, and the pass takes them; a
// tileset loaded without the option has none; bad settings are refused.
#include "TiledCity.h"
#include "loaders/tiles/Tileset.h"
#include "sg/cull/CullTraversal.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace sg;

namespace {
constexpr int kN = 16;

// The street's first views, each settled, culled with the occlusion pass: candidates and entries culled, summed.
std::pair<uint64_t, uint64_t> streetOcclusion(const TilesetOptions& to, const std::string& name) {
    Tileset ts = loadTileset(testutil::writeTiledCity(kN, 180, name), to);
    Scene scene(ts.root());
    PagerSettings ps;
    ps.loaderThreads = 2;
    Pager pager(scene, ts.loadFunction(), ps);
    uint64_t frame = 0, candidates = 0, culled = 0;
    CullTraversal cull;
    CullSettings occl;
    occl.occlusion.mode = OcclusionMode::EveryFrame;
    for (int f = 0; f < scenes::kStreetFrames; f += scenes::kStreetFrames / 6) {
        const Camera cam = scenes::cityStreetCamera(kN, f, 320, 180);
        testutil::settleView(pager, scene, cam, frame);
        DrawList list;
        CullStats st;
        cull.cull(scene, cam, occl, list, st);
        candidates += st.occluderCandidates;
        culled += st.culledOcclusion;
    }
    return {candidates, culled};
}
}  // namespace

TEST(TilesetOccludersLoad, LoadsOnTwoThreadsMakeTheOccludersThePassTakes) {
    TilesetOptions to;
    to.generateOccluders = true;
    const auto [candidates, culled] = streetOcclusion(to, "threads");
    EXPECT_GT(candidates, 0u);
    EXPECT_GT(culled, 0u);
}

TEST(TilesetOccludersLoad, WithoutTheOptionATilesetHasNoOccluders) {
    const auto [candidates, culled] = streetOcclusion(TilesetOptions{}, "none");
    EXPECT_EQ(candidates, 0u);
    EXPECT_EQ(culled, 0u);
}

TEST(TilesetOccludersLoad, BadSettingsAreRefusedNamingTheFunction) {
    TilesetOptions to;
    to.generateOccluders = true;
    to.occluders.voxels = 0;
    try {
        loadTileset("/nonexistent/tileset.json", to);
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("loadTileset()"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("voxels"), std::string::npos) << e.what();
    }
}
