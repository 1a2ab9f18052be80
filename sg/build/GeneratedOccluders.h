// Occluders made from the geometry itself, for scenes nobody placed Occluder nodes in (a glTF file, a tileset, a
// capture): boxes inside closed meshes, large planar faces of open ones. Each is provably inside what it stands for,
// so the occlusion pass stays conservative with them (the argument is in GeneratedOccluders.cpp; tests/scene/
// GeneratedOccludersTest.cpp checks it with random rays).
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"

#include <cstdint>
#include <vector>

namespace sg {

class Node;

struct OccluderGenSettings {
    // Cells along a closed mesh's longest axis when looking for boxes inside it, at most (fewer for meshes of few
    // triangles: 4 times the cube root of their count, at least 8).
    uint32_t voxels = 24;
    uint32_t maxBoxes = 4;          // per closed mesh, largest first
    double minBoxShare = 0.05;      // boxes below this share of the mesh bound's volume are left out
    uint32_t maxPolygons = 16;      // per open mesh, largest first
    double minPolygonShare = 0.05;  // polygons below this share of the bound's largest face area are left out
    // Open meshes: boxes inside the solid their parts bound once each opening (a loop of the boundary) is closed by a
    // cap in its plane, used while the eye is on the solid's side of every such plane (MeshOccluders::cappedBoxes);
    // a mesh that gets such boxes gets no polygons. At most maxOpenings loops, each within openingDepth (a share of
    // the bound's diagonal) of its plane; a part with an opening that is not is left out.
    bool capOpenings = true;
    uint32_t maxOpenings = 8;
    double openingDepth = 0.02;
    // generateOccluders keeps the major occluders only: those whose largest face is at least this share of the largest
    // generated in the subtree (a car beside a tower, a desk beside a wall would take a wall's place in the pass).
    double minMajorShare = 0.02;
    // Throws std::invalid_argument naming `fn` and the setting: voxels not in 1..256, maxBoxes or maxPolygons above
    // 64, maxOpenings above 64, a share or openingDepth not in [0, 1].
    void validate(const char* fn) const;
};

// A mesh's occluders, in its frame.
struct MeshOccluders {
    bool closed = false;     // Mesh::closed(): the boxes are inside its solid; otherwise polygons on its faces
    std::vector<Box> boxes;  // inside the solid: every point of a box has winding number 1 or more
    std::vector<std::vector<dvec3>> polygons;  // convex, on the union of its triangles, counter-clockwise seen
                                               // from the side the triangles face
    // Open meshes (capOpenings): boxes inside the solid bounded by the mesh's closed parts and its parts whose
    // openings lie in planes, those openings closed by caps (flat parts, and parts with an opening off its plane,
    // left out). Each box lies on the positive side of every plane in `openings`, and each opening's cap on the
    // other side: a box stands behind drawn triangles for an eye outside the bound and on the positive side of every
    // plane (Occluder::setOpenings). Empty `openings`: the closed parts alone gave them.
    std::vector<Box> cappedBoxes;
    std::vector<Plane> openings;
    uint64_t voxelsInside = 0;  // closed meshes: grid cells found wholly inside the solid
};

// Boxes for a closed mesh (Mesh::closed()), capped boxes or else polygons for an open one; nothing for a mesh with
// non-finite positions or no triangles. Pure: the same mesh and settings give the same shapes.
MeshOccluders meshOccluders(const Mesh& mesh, const OccluderGenSettings& s = {});

struct OccluderGenStats {
    uint64_t geometries = 0;      // Geometry nodes (an LOD counted once) that got occluders, after the major filter
    uint64_t meshes = 0;          // distinct meshes analysed
    uint64_t meshTriangles = 0;   // their triangles
    uint64_t sceneTriangles = 0;  // triangles of every Geometry visited (a shared mesh counted at each use)
    uint64_t boxes = 0, polygons = 0;  // Occluder nodes added
    uint64_t lods = 0;                 // of those, standing for an LOD (used while it shows a level)
    uint64_t minor = 0;                // left out as minor (OccluderGenSettings::minMajorShare)
    uint64_t enclosed = 0;             // polygons left out within the bound of a mesh beside them that got boxes
    uint64_t skipped = 0;              // Geometry nodes left without: blended or alpha-masked, masked themselves,
                                       // under a Billboard or Instance prototype, a Switch's own child, or beside an
                                       // authored occluder
    double ms = 0.0;                   // wall time
};

// Adds Occluder nodes for the geometry below `root`: beside each opaque Geometry (in its parent Group or Transform, in
// its frame) its mesh's shapes; beside an LOD the boxes inside every one of its levels (an LOD whose levels are all
// closed meshes), used only while the LOD shows a level (Occluder::setShownWith). Below a Switch or a masked node
// they are used while the Switch shows them and the traversal mask sees the node (the image's copies of both); a
// Switch's own Geometry children get none (an occluder among its children would shift them). Below a PagedLOD (its
// coarse children, and its detail when attached) they are used while the cull draws them. Geometry masked
// itself, under a Billboard or an Instance's prototype gets none (the pass would not use them); a parent that already
// has an Occluder child keeps its authored ones and gets no generated ones; only major occluders are kept
// (OccluderGenSettings::minMajorShare). Meshes shared by many Geometry nodes are analysed once. Running it again first
// removes the occluders it added before.
OccluderGenStats generateOccluders(Node& root, const OccluderGenSettings& s = {});

// Removes the Occluder nodes below `root` (generated ones only when `generatedOnly`); returns how many.
size_t removeOccluders(Node& root, bool generatedOnly = false);

}  // namespace sg
