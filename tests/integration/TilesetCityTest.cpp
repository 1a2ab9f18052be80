// The city written as tiles by writeTileset and read back by loadTileset, paged by the pager: every view, once
// the pager has nothing left to load for it, equals the render of the city held in memory pixel for pixel (the
// tiles reproduce the graph's LOD choices), whether the view shows leaves, exact proxies or both; written as
// explicit tiles or as implicit tiling (whose tiles' boxes and errors are tile metadata).
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetWrite.h"
#include "loaders/tiles/internal/SharedMeshes.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "sg/scene/internal/DistinctGeometries.h"
#include "testbed/City.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

using namespace sg;

namespace {

constexpr int kW = 320, kH = 180;

Image draw(Renderer& r, Scene& scene, CullTraversal& cull, const Camera& cam, CullStats& stats) {
    DrawList list;
    stats = CullStats{};
    cull.cull(scene, cam, CullSettings{}, list, stats);
    r.draw(list, cam);
    return r.readColor();
}

// The city of n x n cells written as tiles (`implicit`: as implicit tiling), each view settled, against the city
// in memory; returns the settled views' pictures.
std::vector<Image> settledViewsEqualTheCity(int n, bool implicit) {
    const std::string dir = ::testing::TempDir() + (implicit ? "sgkit_tiles_city_implicit" : "sgkit_tiles_city");
    std::filesystem::remove_all(dir);
    TileWriteOptions wo;
    wo.maxTrianglesPerTile = 60000;  // a few levels for a small city
    wo.referenceHeightPixels = kH;   // the geometric errors for this view's pixels
    wo.implicit = implicit;
    const TileWriteReport report = writeTileset(*scenes::buildCity({n, false}), dir, wo);
    EXPECT_GT(report.tiles, 4u);
    std::vector<Image> pictures;

    Tileset ts = loadTileset(dir + "/tileset.json");
    Scene tiles(ts.root());
    Pager pager(tiles, ts.loadFunction());
    Scene city(scenes::buildCity({n, false}));
    city.update();
    OsmesaContext context(kW, kH);
    Renderer renderer;
    CullTraversal tileCull, cityCull;

    // Views from far (proxies) to near (leaves): the orbit at three distances and the street.
    std::vector<Camera> cams;
    for (int f = 0; f < scenes::kOrbitFrames; f += 20) cams.push_back(scenes::cityOrbitCamera(n, f, kW, kH));
    for (int f = 0; f < scenes::kStreetFrames; f += 40) cams.push_back(scenes::cityStreetCamera(n, f, kW, kH));
    for (double d : {100.0, 600.0, 1500.0}) {
        Camera c;
        c.setViewport(kW, kH);
        c.setPerspective(60.0, double(kW) / kH, 1.0, 3000.0);
        c.setLookAt(dvec3(10.0 * n - d, 10.0 * n - d, 0.4 * d), dvec3(10.0 * n, 10.0 * n, 0), dvec3(0, 0, 1));
        cams.push_back(c);
    }
    uint64_t frame = 0;
    uint64_t minWanted = UINT64_MAX, maxWanted = 0;
    for (size_t k = 0; k < cams.size(); ++k) {
        CullStats ts1;
        for (int settle = 0;; ++settle) {  // frames until nothing is asked for, queued or loading
            ++frame;
            pager.update(FrameInfo{frame, double(frame)});
            tiles.update(FrameInfo{frame, double(frame)});
            draw(renderer, tiles, tileCull, cams[k], ts1);
            const bool busy = pager.stats().queued > 0 || pager.stats().loading;
            if (!busy && ts1.pagedRequested == 0 && ts1.pagedCoarse == 0) break;
            if (settle >= 200) {
                ADD_FAILURE() << "view " << k << " never settles";
                return pictures;
            }
            pager.waitIdle();
        }
        CullStats cs;
        const Image got = draw(renderer, tiles, tileCull, cams[k], ts1);
        const Image want = draw(renderer, city, cityCull, cams[k], cs);
        EXPECT_EQ(countDifferingPixels(got, want), 0u) << "view " << k;
        EXPECT_EQ(ts1.triangles, cs.triangles) << "view " << k;
        EXPECT_GT(cs.triangles, 0u) << "view " << k;
        pictures.push_back(got);
        minWanted = std::min(minWanted, ts1.pagedWanted);
        maxWanted = std::max(maxWanted, ts1.pagedWanted);
    }
    EXPECT_LT(minWanted, maxWanted);  // far views drew proxies where near ones refined to leaves

    // Every tile's file carries its own copy of the building meshes; the loads made equal ones one mesh, so
    // the graph holds no two meshes with the same arrays (and the pictures above were drawn that way).
    EXPECT_GT(ts.counts().sharedMeshes, 0u);
    std::map<uint64_t, std::vector<const Mesh*>> byHash;
    forEachDistinctGeometry(*ts.root(), [&](const Geometry& g) {
        auto& same = byHash[tiles::meshHash(*g.mesh())];
        if (std::find(same.begin(), same.end(), g.mesh()) == same.end()) same.push_back(g.mesh());
    });
    size_t held = 0;
    for (auto& [h, meshes] : byHash) {
        held += meshes.size();
        for (size_t i = 1; i < meshes.size(); ++i) EXPECT_FALSE(tiles::sameMesh(*meshes[0], *meshes[i]));
    }
    EXPECT_GT(held, 0u);
    return pictures;
}

}  // namespace

TEST(TilesetCity, SettledViewsEqualTheCityInMemory) { settledViewsEqualTheCity(24, false); }

// Implicit tiling: the tiles' own boxes and errors come from the subtrees' tile metadata, so each view settles on
// the same picture as the explicit tileset's (and the city's); with the implied boxes and halved errors it would not.
TEST(TilesetCity, ImplicitTilingSettlesOnTheSamePictures) {
    const std::vector<Image> implicit = settledViewsEqualTheCity(24, true);
    const std::vector<Image> explicitTiles = settledViewsEqualTheCity(24, false);
    ASSERT_EQ(implicit.size(), explicitTiles.size());
    for (size_t k = 0; k < implicit.size(); ++k)
        EXPECT_EQ(countDifferingPixels(implicit[k], explicitTiles[k]), 0u) << "view " << k;
}
