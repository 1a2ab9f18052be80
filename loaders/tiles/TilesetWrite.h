// A scene cut into a quadtree of tiles and written as OGC 3D Tiles 1.1: dir/tileset.json and one .glb per
// tile content in dir/tiles, for any 3D Tiles reader (sg::loadTileset, CesiumJS, 3d-tiles-tools).
#pragma once
#include "sg/core/Node.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace sg {

struct TileWriteOptions {
    // A tile is split (quadtree in x and y; scenes are +Z up) until its triangles, counting the finest child of
    // each LOD only, are at most this, or it holds a single unit (a subtree written whole).
    size_t maxTrianglesPerTile = 200000;
    // The reader's default; with the reference view it turns distances into geometric errors.
    double maximumScreenSpaceError = 16.0;
    // The reference view: a geometric error e and a distance D are related by e = maxSSE * D / K, with
    // K = heightPixels / (2 tan(fovY / 2)); a reader with this view refines a tile of error e nearer than D.
    int referenceHeightPixels = 720;
    double referenceFovYDegrees = 60.0;
    // How far the scene can be seen (the city's far plane): a tile without content refines within it.
    double farDistance = 3000.0;
    // Exact: an inner tile holds its subtree with each distance LOD reduced to the children it can still show
    // from outside the tile's refinement distance, so that the tileset draws what the graph's LODs would, pixel
    // for pixel; no content where that is impossible or over the limit. Simplified: an inner tile holds the
    // merged and simplified (meshoptimizer) finest levels of its children, half their triangles.
    enum class Proxies { Exact, Simplified } proxies = Proxies::Exact;
    // Repeated leaves (a mesh, or an LOD of one mesh, placed again and again) written as instances
    // (EXT_mesh_gpu_instancing): a city's tile becomes kilobytes of JSON instead of megabytes, and reads as fast.
    bool instancing = true;
    // The same tiles as 3D Tiles 1.1 implicit tiling: a tileset.json of one tile, the tree's availability and each
    // tile's box and geometric error (TILE_BOUNDING_BOX and TILE_GEOMETRIC_ERROR tile metadata, in the root's
    // frame) in subtree files dir/subtrees/{level}/{x}/{y}.subtree, contents in dir/tiles/{level}/{x}/{y}.glb
    // holding their offset from the root's centre. Opening the tileset then reads the root's subtree only.
    bool implicit = false;
    // Called as tiles are written: the fraction of the scene written, in [0, 1], and the stage.
    std::function<void(double fraction, const std::string& stage)> progress;
};

struct TileWriteReport {
    size_t tiles = 0, contents = 0, bytes = 0;  // bytes: tileset.json, every .glb and subtree file
    double seconds = 0;
    std::vector<std::string> warnings;
};

// Writes dir/tileset.json and dir/tiles/*.glb (creating dir), the scene below `root` (+Z up, metres) in its
// world frame. Every tile has a box bounding volume, a geometric error (0 at leaves), refine REPLACE and a
// transform holding its centre (its content and box are relative to it, so that coordinates far from the origin
// keep their precision; implicit tiling: the root's transform holds its centre, a content's root node its
// offset from it); contents are glTF +Y up, as the specification has them. A fully refined tileset draws
// exactly the scene: sgkit's node kinds travel in the contents' extras as saveGltf writes them. Throws
// std::runtime_error naming the path when it cannot write, std::invalid_argument for impossible options.
TileWriteReport writeTileset(const Node& root, const std::string& dir, const TileWriteOptions& options = {});

}  // namespace sg
