// Occluders made from a tileset's tiles as they are read (TilesetOptions::generateOccluders): the city written as
// tiles, paged in view by view, draws exactly the pixels of the unculled render of the same tiles with the occlusion
// pass on, with the tree and with the map, and culls most of the street's triangles as the city's authored boxes do.
#include "Scaled.h"
#include "TiledCity.h"
#include "loaders/tiles/Tileset.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "testbed/City.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace sg;

namespace {
constexpr int kW = 320, kH = 180, kN = 24;
}  // namespace

TEST(TilesetOccluders, TilesOccludersAreExactAndCullTheStreet) {
    const std::string file = testutil::writeTiledCity(kN, kH, "occluders");
    TilesetOptions to;
    to.generateOccluders = true;
    Tileset ts = loadTileset(file, to);
    Scene scene(ts.root());
    Pager pager(scene, ts.loadFunction());
    OsmesaContext context(kW, kH);
    Renderer renderer;

    std::vector<Camera> cams;
    const int every = std::max(1, scenes::kStreetFrames / testutil::scaled(24));
    for (int f = 0; f < scenes::kStreetFrames; f += every) cams.push_back(scenes::cityStreetCamera(kN, f, kW, kH));
    for (int f = 0; f < scenes::kOrbitFrames; f += scenes::kOrbitFrames / 4)  // far: coarse tiles too
        cams.push_back(scenes::cityOrbitCamera(kN, f, kW, kH));

    uint64_t frame = 0;
    for (OcclusionMethod method : {OcclusionMethod::Tree, OcclusionMethod::Hom}) {
        CullSettings none, frustum, occl;
        none.strategy = CullStrategy::None;
        frustum.occlusion.mode = OcclusionMode::Off;
        occl.occlusion.mode = OcclusionMode::EveryFrame;
        occl.occlusion.method = method;
        CullTraversal cullNone, cullFrustum, cullOccl;
        uint64_t trisFrustum = 0, trisOccl = 0, culled = 0, used = 0;
        for (size_t v = 0; v < cams.size(); ++v) {
            testutil::settleView(pager, scene, cams[v], frame);
            DrawList list;
            CullStats st;
            cullNone.cull(scene, cams[v], none, list, st);
            renderer.draw(list, cams[v]);
            const Image want = renderer.readColor();
            cullFrustum.cull(scene, cams[v], frustum, list, st);
            trisFrustum += st.triangles;
            cullOccl.cull(scene, cams[v], occl, list, st);
            trisOccl += st.triangles;
            culled += st.culledOcclusion;
            used += st.occludersUsed;
            renderer.draw(list, cams[v]);
            EXPECT_EQ(countDifferingPixels(renderer.readColor(), want), 0u)
                << "view " << v << ", method " << int(method);
        }
        EXPECT_GT(used, 0u);
        EXPECT_GT(culled, 0u);
        // The city's authored boxes leave about a seventh of the street's frustum triangles (docs/benchmarks.md).
        EXPECT_LT(double(trisOccl), 0.5 * double(trisFrustum)) << "method " << int(method);
    }
}
