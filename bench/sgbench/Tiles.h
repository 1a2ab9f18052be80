// What the paths of `sgbench tiles` share: the settled test, the points' shading from the options, and the factory
// walkthrough's path (TilesWalk.cpp), which runTiles (TilesBench.cpp) hands its viewer to.
#pragma once
#include "loaders/tiles/Tileset.h"
#include "sg/core/Camera.h"
#include "sg/core/Math.h"
#include "sg/gl/PointShading.h"
#include "sg/viewer/Viewer.h"
#include "sgbench/Bench.h"

#include <string>
#include <vector>

namespace bench {

// Frames at the view's camera until it is settled (nothing queued, loading or waiting for its upload, nothing asked
// for, nothing wanted drawn coarse), at most `most`: the frames run.
int settleTiles(sg::Viewer& viewer, sg::View& view, sg::Pager& pager, int most);

// The shading --point-size PX (1 to 64), --round (discs) and --edl (eye-dome lighting) ask for; the renderer's
// defaults otherwise. Throws std::invalid_argument naming the option for a size that is not a number in range.
sg::PointShading pointShadingFromArgs(const Args& a);

// The factory walkthrough (testbed/FactoryWalk.h) as `frames` cameras of w x h, from a factory built for them alone
// and freed before returning; `site` gets the factory's world box (where its scan's tiles must be).
std::vector<sg::Camera> factoryWalkCameras(int frames, int w, int h, sg::Box& site);

// A tileset opened and put in a paging viewer by runTiles, for a path of its own file to fly.
struct TilesFlight {
    std::string file;
    sg::TilesetOptions options;  // as the tileset was opened: a second copy of it is opened alike
    const sg::Tileset& tileset;
    sg::Viewer& viewer;
    sg::View& view;
    sg::Pager& pager;
    double openMs = 0.0;      // loadTileset's time
    double rssStartMb = 0.0;  // before the tileset was opened
};

// sgbench tiles --path factory-walk [--settle-check [--views K]]: TilesWalk.cpp's header says what it measures.
int flyFactoryWalk(const Args& a, const TilesFlight& t, const std::vector<sg::Camera>& cams, const sg::Box& site);

// sgbench tiles --path loads [--loads K] [--runs R]: the load function timed alone, tile after tile, against the
// parse of the same tileset's contents (TilesLoad.cpp).
int measureTileLoads(const Args& a, const std::string& file, const sg::TilesetOptions& options);

}  // namespace bench
