// The benchmark city written as tiles (writeTileset) and views of it settled by a pager, for the tests of tilesets.
#pragma once
#include "loaders/tiles/TilesetWrite.h"
#include "sg/cull/CullTraversal.h"
#include "sg/paging/Pager.h"
#include "testbed/City.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace testutil {

// The city of n x n cells as tiles in a directory of its own under the test directory (`name`: tests run side by
// side); returns its tileset.json.
inline std::string writeTiledCity(int n, int heightPixels, const std::string& name) {
    const std::string dir = ::testing::TempDir() + "sgkit_tiled_city_" + name;
    std::filesystem::remove_all(dir);
    sg::TileWriteOptions wo;
    wo.maxTrianglesPerTile = 60000;  // a few levels for a small city: coarse tiles and leaves in one view
    wo.referenceHeightPixels = heightPixels;
    sg::writeTileset(*scenes::buildCity({n, false}), dir, wo);
    return dir + "/tileset.json";
}

// Frames at the view, culled with culling off, until every tile it wants is attached: each cull of the view then
// sees the same tiles. `frame` counts the frames on.
inline void settleView(sg::Pager& pager, sg::Scene& scene, const sg::Camera& cam, uint64_t& frame) {
    sg::CullTraversal cull;
    sg::CullSettings none;
    none.strategy = sg::CullStrategy::None;
    sg::DrawList list;
    sg::CullStats st;
    for (int k = 0; k < 200; ++k) {
        ++frame;
        pager.update(sg::FrameInfo{frame, double(frame)});
        scene.update(sg::FrameInfo{frame, double(frame)});
        cull.cull(scene, cam, none, list, st);
        if (pager.stats().queued == 0 && !pager.stats().loading && st.pagedRequested == 0 && st.pagedCoarse == 0)
            return;
        pager.waitIdle();
    }
    ADD_FAILURE() << "the view never settles";
}

}  // namespace testutil
