// Tilesets in pixels: the same tiles placed millions of metres from the origin (Earth-centred data) draw as
// they do at the origin, through the renderer's camera-relative path; so do the tiles writeTileset writes of a
// scene that far out, explicit or implicit.
#include "RenderUtil.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetWrite.h"
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "testbed/City.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace sg;
namespace fs = std::filesystem;

namespace {

constexpr int kW = 200, kH = 150;

// A tileset of a 4 x 4 grid of boxes (one glb per child, one for the root) below a root whose transform is
// `rootMatrix` (column-major, as written).
std::string writeGrid(const std::string& dir, const dmat4& rootMatrix) {
    fs::create_directories(dir);
    dmat4 zUpToYUp(1.0);
    zUpToYUp[1] = dvec4(0, 0, -1, 0);
    zUpToYUp[2] = dvec4(0, 1, 0, 0);
    std::ostringstream children;
    for (int i = 0; i < 16; ++i) {
        const dvec3 mn(10.0 * (i % 4) + 1, 10.0 * (i / 4) + 1, 0), mx = mn + dvec3(7, 7, 3 + i % 5);
        auto t = make<Transform>(zUpToYUp);
        t->addChild(make<Geometry>(makeBoxMesh(mn, mx, 3), make<Material>(vec4(0.2f + 0.05f * i, 0.5f, 0.3f, 1))));
        auto root = make<Group>();
        root->addChild(t);
        saveGltf(*root, dir + "/b" + std::to_string(i) + ".glb");
        const dvec3 c = 0.5 * (mn + mx), h = 0.5 * (mx - mn);
        children << (i ? "," : "") << R"({"boundingVolume": {"box": [)" << c.x << "," << c.y << "," << c.z << "," << h.x
                 << ",0,0,0," << h.y << ",0,0,0," << h.z << R"(]}, "geometricError": 0, "content": {"uri": "b)" << i
                 << R"(.glb"}})";
    }
    std::ostringstream m;
    m.precision(17);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m << (c || r ? "," : "") << rootMatrix[c][r];
    std::ofstream(dir + "/tileset.json")
        << R"({"asset": {"version": "1.1"}, "geometricError": 50, "root": {"transform": [)" << m.str()
        << R"(], "boundingVolume": {"box": [20,20,5, 20,0,0, 0,20,0, 0,0,5]}, "geometricError": 20, "refine": "REPLACE",
        "children": [)"
        << children.str() << "]}}";
    return dir + "/tileset.json";
}

Image render(Renderer& r, const Tileset& ts, const Camera& cam) {
    refineAll(*ts.root(), ts.loadFunction());
    return testutil::drawGraph(r, ts.root(), cam);
}

}  // namespace

TEST(TilesetImage, EarthCentredTilesDrawAsAtTheOrigin) {
    const std::string dir = ::testing::TempDir() + "sgkit_tiles_ecef";
    // An east-north-up frame on the equator-ish: a rotation and a translation of millions of metres, with
    // coordinates exact in double so that both views are the same up to the offset.
    const dvec3 offset(4096000.0, 2048000.0, 4194304.0);
    dmat4 rot = glm::rotate(dmat4(1.0), 0.75, dvec3(0, 0, 1));
    const dmat4 far = glm::translate(dmat4(1.0), offset) * rot;
    Tileset atOrigin = loadTileset(writeGrid(dir + "/origin", rot));
    Tileset atEarth = loadTileset(writeGrid(dir + "/earth", far));
    OsmesaContext context(kW, kH);
    Renderer renderer;
    size_t covered = 0;
    const dvec3 eyes[] = {{-30.5, -20.25, 25.0}, {60.0, 10.5, 8.0}, {5.0, 5.0, 40.0}};
    for (const dvec3& e : eyes) {
        const dvec3 target = dvec3(rot * dvec4(20, 20, 2, 1));
        Camera a, b;
        a.setViewport(kW, kH);
        a.setPerspective(50.0, double(kW) / kH, 0.5, 500.0);
        b = a;
        a.setLookAt(e, target, dvec3(0, 0, 1));
        b.setLookAt(e + offset, target + offset, dvec3(0, 0, 1));
        const Image ia = render(renderer, atOrigin, a);
        const Image ib = render(renderer, atEarth, b);
        EXPECT_EQ(countDifferingPixels(ia, ib, 0), 0u) << "eye " << e.x << ", " << e.y << ", " << e.z;
        Image clear = ia;
        for (size_t i = 0; i < clear.rgba.size(); i += 4)
            std::copy(ia.rgba.begin(), ia.rgba.begin() + 4, clear.rgba.begin() + long(i));
        covered += countDifferingPixels(ia, clear, 0);
    }
    EXPECT_GT(covered, size_t(kW * kH / 4));  // the views see the tiles
}

// The city written 6 million metres from the origin: its tiles (their centres in each tile's transform, or for
// implicit tiling in the root's transform and each content's root node, in double) draw, fully refined, what the
// city at the origin draws, pixel for pixel. Float contents at that distance would be off by half a metre.
TEST(TilesetImage, TilesWrittenFarFromTheOriginDrawAsAtTheOrigin) {
    const dvec3 offset(4096000.0, 2048000.0, 4194304.0);  // exact in double, as the eyes below
    const int n = 8;
    auto far = make<Transform>(glm::translate(dmat4(1.0), offset));
    far->addChild(scenes::buildCity({n, false}));
    auto city = scenes::buildCity({n, false});
    OsmesaContext context(kW, kH);
    Renderer renderer;
    for (bool implicit : {false, true}) {
        const std::string dir = ::testing::TempDir() + (implicit ? "sgkit_tiles_far_implicit" : "sgkit_tiles_far");
        fs::remove_all(dir);
        TileWriteOptions options;
        options.maxTrianglesPerTile = 10000;  // a few levels
        options.implicit = implicit;
        const TileWriteReport report = writeTileset(*far, dir, options);
        EXPECT_GT(report.tiles, 4u);
        Tileset tiles = loadTileset(dir + "/tileset.json");
        size_t covered = 0;
        for (const dvec3& e : {dvec3(-20.5, -30.25, 40.0), dvec3(80.0, 60.5, 6.0), dvec3(200.0, -50.0, 120.0)}) {
            Camera a, b;
            a.setViewport(kW, kH);
            a.setPerspective(50.0, double(kW) / kH, 0.5, 3000.0);
            b = a;
            const dvec3 target(10.0 * n, 10.0 * n, 0.0);
            a.setLookAt(e, target, dvec3(0, 0, 1));
            b.setLookAt(e + offset, target + offset, dvec3(0, 0, 1));
            const Image want = testutil::drawGraph(renderer, city, a);
            const Image got = render(renderer, tiles, b);
            EXPECT_EQ(countDifferingPixels(got, want, 0), 0u)
                << (implicit ? "implicit" : "explicit") << ", eye " << e.x << ", " << e.y << ", " << e.z;
            Image clear = want;
            for (size_t i = 0; i < clear.rgba.size(); i += 4)
                std::copy(want.rgba.begin(), want.rgba.begin() + 4, clear.rgba.begin() + long(i));
            covered += countDifferingPixels(want, clear, 0);
        }
        EXPECT_GT(covered, size_t(kW * kH / 4));  // the views see the city
    }
}
