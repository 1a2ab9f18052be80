// buildPointTiles: a scan of any size written as an OGC 3D Tiles octree of point tiles (glTF, or .pnts for 3D Tiles
// 1.0 readers), out of core, and in shards that separate processes (or machines sharing the output folder) can build.
//
// How (after PotreeConverter 2, Schuetz et al. 2020): the scan's bounds are made a cube. Pass 1 counts the points in
// each cell of a 128^3 grid over it; the count pyramid is cut, from the top, into chunks (octree nodes) of at most
// chunkPoints. Pass 2 appends each point to its chunk's temporary file. Each chunk is then built alone in memory:
// split into octree nodes until a node holds at most maxPointsPerTile; bottom-up, each inner node takes one point per
// cell of a gridCells^3 grid over its cube from its children's points (the one nearest the cell's centre, ties to the
// earlier point of the scan), which are removed from the children: additive refinement ("ADD"), each level a
// subsample of the one below. The merge builds the levels above the chunks the same way from the chunk roots' points
// and writes tileset.json.
//
// Output in `outDir`: tileset.json and tiles/<octree path>.glb (or .pnts), the path "r", then a digit per level,
// the child's index (bit 0: +x half, bit 1: +y, bit 2: +z): r, r0, r07. A tile's geometricError is its sample grid's
// cell size; a leaf's is the cell size, from its cube's grid down by halvings (at most 10), at which each of its
// points would have a cell of its own: the spacing its points were kept at. Tight boxes of each subtree's points.
// The bytes depend only on the scan and the options, never on the number of shards nor on the time.
//
// Resident memory is bounded whatever the scan's size: the count grid (128^3 eight-byte counts and four-byte chunk
// ids, ~26 MiB), one chunk's points (chunkPoints x 40 bytes, up to three times over while it is read and split),
// pass 2's buffers (2^20 points, 40 MiB) and, in the merge, one node's and its eight children's samples. A chunk is
// divided further on disk when it holds more than chunkPoints (a count-grid cell near a scanner's station): its file
// split by octants, streamed, until each part fits (the levels above the parts are then the merge's).
#pragma once
#include "loaders/points/Scan.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace sg {

struct PointTileOptions {
    size_t maxPointsPerTile = 50000;  // a leaf holds at most this many points (a node at the deepest level excepted)
    size_t chunkPoints = 2'000'000;   // points a chunk holds in memory while built (at least maxPointsPerTile)
    int gridCells = 128;              // sample grid per node edge, 1 to 1024
    bool pnts = false;                // .pnts tiles and tileset version 1.0 instead of glTF tiles and 1.1
    // Shard: builds the chunks whose index % shards == shard, writing their tiles and, for the merge, each chunk
    // root's points in outDir/.parts. Merge: once every shard is done, builds the levels above the chunks from
    // outDir/.parts, writes tileset.json and removes .parts. All: shard 0 of 1, then the merge.
    enum Stage { All, Shard, Merge } stage = All;
    int shard = 0, shards = 1;
    std::string tempDir;  // the chunks' temporary files; empty: outDir/.tmp-<shard> (removed when done)
};

struct PointTileStats {
    uint64_t points = 0;  // points of the scan
    size_t tiles = 0;     // tile files written by this call
    int levels = 0;       // octree levels of the tileset (after a merge; a shard's: below its chunks)
    double seconds = 0.0;
    uint64_t bytes = 0;  // bytes of the files written (tiles, tileset.json, .parts)
    // The most points one chunk held in memory (at most chunkPoints: denser chunks are split on disk first).
    uint64_t largestChunk = 0;
};

// Throws std::invalid_argument for bad options (the message starts with "buildPointTiles(): "), std::runtime_error
// for an empty scan, a scan that changes between passes, a merge missing a shard's chunks or a file that cannot be
// written, and what the reader throws (sg::LoadError).
PointTileStats buildPointTiles(ScanReader& scan, const std::string& outDir, const PointTileOptions& options);

}  // namespace sg
