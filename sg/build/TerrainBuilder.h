// TerrainBuilder: a scene graph from a height field, as a quadtree of Groups over tiles, each tile an LOD of
// levels that meet their neighbours without cracks at any mix of levels.
#pragma once
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "sg/core/Material.h"
#include "sg/core/Math.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace sg {

// One level of a square tile of `per` x `per` cells: the grid points it uses (tile-local, 0..per, in row
// order) and its triangles (indices into `points`, counter-clockwise seen from +Z). With cells == per it is
// the full grid, each cell split along its (i, j)-(i+1, j+1) diagonal. Coarser, it is a grid through every
// (per / cells)-th point inside the tile, stitched by fans to the tile's border kept at full resolution:
// every level of every tile has the finest border, so neighbours at any levels meet without cracks.
struct TerrainTileGrid {
    int per = 0;
    std::vector<glm::ivec2> points;
    std::vector<uint32_t> indices;
};
// Throws std::invalid_argument unless 2 <= cells <= per.
TerrainTileGrid terrainTileGrid(int per, int cells);
// Cells per side of a tile's levels: `per`, then 2, 4, 8, ... times coarser, `levels` in all at most (fewer
// when the tile is too small to have them all: no level has fewer than 2 cells a side).
std::vector<int> terrainLevelCells(int per, int levels);
// The largest vertical distance between a level's surface and the full-resolution surface over the tile
// (the height field's cells split along their (i, j)-(i+1, j+1) diagonal); `height(i, j)` gives the sample
// at tile-local grid point (i, j). Both surfaces are linear on every piece of their overlay, so the largest
// lies at a grid point inside a triangle or where a triangle's edge crosses a cell's edge: exact.
double terrainLevelError(const TerrainTileGrid& level, const std::function<double(int, int)>& height);

struct TerrainParams {
    int tileSamples = 33;  // samples per tile side: 2^m + 1, at least 3, at most the field's
    int levels = 5;        // LOD levels per tile: the full grid, then 2, 4, 8, 16 times coarser
    // A coarse level is shown from where its exact vertical error projects to at most this many pixels on
    // a viewport `viewportHeight` pixels high with a vertical field of view of `fovyDegrees`.
    double pixelError = 1.0;
    double fovyDegrees = 60.0;
    int viewportHeight = 768;
    ref_ptr<Material> material;  // shared by every tile; a plain earth colour when null
    // Pixels per radian of the view the pixel error refers to; when positive it replaces the one derived from
    // fovyDegrees and viewportHeight (e.g. sg::kDefaultPixelsPerRadian, which makeLod's meshes use).
    double pixelsPerRadian = 0.0;
    // The tiles as the root's children in row order (tile (ti, tj) at tj * tilesPerSide + ti), without the
    // quadtree's Groups. Then n - 1 need only be a multiple of tileSamples - 1 (tileSamples >= 3).
    bool flat = false;
    // Vertices at origin + (i, j, 0) * spacing + (0, 0, height), rounded once to float, under a plain Group:
    // for a terrain near the origin that shares its frame with other geometry. Otherwise vertices are
    // relative to the origin, which the root Transform holds in double (no float jitter far from the origin).
    bool originInVertices = false;
    // Per-vertex texture coordinates and colours, from the vertex's point (origin included, in double); no
    // such attribute when empty. Called from worker threads, so they must be safe to call concurrently.
    std::function<vec2(const dvec3&)> uv;
    std::function<vec4(const dvec3&)> color;
    // Occluder boxes below the surface, beside each tile's LOD (its siblings, after it, in its frame): the tile split
    // into occluderBlocks x occluderBlocks blocks, each a box from below the terrain up to just under the lowest vertex
    // of any level's triangles over the block. Used by the occlusion pass while the eye is over the terrain and
    // higher than the surface near it (Occluder::setBelowSurface): a town behind a hill is culled. With one tile,
    // the tile's LOD and its occluders are put under a Group.
    bool occluders = false;
    int occluderBlocks = 2;  // 1..tileSamples - 1
};

// What buildTerrain made: the graph and its quadtree, for applications that want to find a tile again.
struct Terrain {
    ref_ptr<Group> root;
    // Quadtree nodes in pre-order (the root first, a parent before its children). A leaf is a tile: an LOD
    // whose children are its levels (Geometries), finest first. Interior nodes are Groups of four children
    // (with params.flat, one Group of every tile). quad[0] is `root` with originInVertices, else its child (with
    // params.occluders and one tile, the tile is the child of a Group that is `root` or its child).
    struct QuadNode {
        ref_ptr<Group> node;
        int parent = -1;  // index into quad, -1 for the root
        int depth = 0;
        bool tile = false;
    };
    std::vector<QuadNode> quad;
    int tilesPerSide = 0;
    uint64_t finestTriangles = 0;  // every tile at its finest level
    uint64_t coarsestTriangles = 0;
};

// Builds the terrain of a height field: `heights` row-major (heights[j * n + i] at origin + (i, j, 0) *
// spacing, +Z up), n = samplesPerSide = 2^k + 1 (with params.flat, any n with n - 1 a multiple of
// tileSamples - 1). The quadtree's boxes are the tiles' prisms (x, y of the
// tile, z from its lowest to its highest sample) and their unions (with params.occluders, the Groups' also hold the
// occluder boxes below); spheres are the boxes' half diagonals.
// Throws std::invalid_argument naming the function and the value: n not 2^k + 1 (k >= 1), a height count
// other than n * n, a NaN or infinite height, a spacing that is not positive and finite, a non-finite
// origin, tileSamples not 2^m + 1 in [3, n], levels < 1, a pixel error not positive and finite, a field of
// view outside (0, 180), a viewport height < 1, a pixelsPerRadian that is negative or not finite, occluderBlocks
// outside 1..tileSamples - 1 (with occluders).
Terrain buildTerrain(const std::vector<float>& heights, int samplesPerSide, double spacing, const dvec3& origin,
                     const TerrainParams& params = {});
// The same from heights in double: levels, errors and normals computed from them unrounded.
Terrain buildTerrain(const std::vector<double>& heights, int samplesPerSide, double spacing, const dvec3& origin,
                     const TerrainParams& params = {});

}  // namespace sg
