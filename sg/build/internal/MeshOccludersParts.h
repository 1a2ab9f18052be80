// The parts of meshOccluders (GeneratedOccluders.h) shared by its two files: boxes inside a closed surface
// (MeshOccluders.cpp), and the analysis of open meshes, their polygons and their capped boxes (OpenMeshOccluders.cpp).
// Internal header: not installed (an internal/ folder, cmake/LayerCheck.cmake).
#pragma once
#include "sg/build/GeneratedOccluders.h"

#include <array>
#include <cstdint>
#include <vector>

namespace sg::meshocc {

struct Tri {
    dvec3 a, b, c;
};

// Boxes inside the solid `tris` bound (a closed surface within `b`), largest first; made of cells wholly on the
// positive side of every plane in `beyond`, so on that side themselves. `meshTriangles` sizes the grid.
std::vector<Box> boxesInside(const std::vector<Tri>& tris, const Box& b, size_t meshTriangles,
                             const OccluderGenSettings& s, uint64_t& voxelsInside,
                             const std::vector<Plane>& beyond = {});

// A mesh's corners welded: positions equal bit for bit share an id (vid, per vertex); pos: each id's position; and
// its triangles by welded corners, those with a repeated corner (no area, no edge of their own) left out.
struct Welded {
    std::vector<uint32_t> vid;
    std::vector<dvec3> pos;
    std::vector<std::array<uint32_t, 3>> tris;
    explicit Welded(const Mesh& mesh);
};

// Polygons on an open mesh, and boxes inside it with its planar openings capped (MeshOccluders::cappedBoxes).
void openPolygons(const Mesh& mesh, const Welded& w, const OccluderGenSettings& s, MeshOccluders& out);
void cappedBoxes(const Mesh& mesh, const Welded& w, const OccluderGenSettings& s, MeshOccluders& out);

}  // namespace sg::meshocc
