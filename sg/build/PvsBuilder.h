// PvsBuilder: computes a PvsTable for a scene offline, by extended projections (Durand et al., SIGGRAPH
// 2000): per view cell, the image entries that the scene's Occluder entries hide from every point of it.
//
// Per cell and per axis direction d (+x, -x, +y, -y, +z, -z): the occluders entirely beyond the cell's face
// along d (by at least maxNear) are projected onto a plane perpendicular to d (which none of them straddles) from the
// cell's 8 corners. An occluder's extended projection is the intersection of its 8 projections (each the
// convex hull of its projected vertices; exact for a convex occluder and a convex cell); it is drawn INNER
// into a grid map (only pixels entirely inside it) with its farthest depth along d, each pixel keeping the
// nearest such depth. An occludee box entirely beyond the face is hidden when its extended projection (the
// convex hull of its 8 corners projected from the 8 cell corners: a superset of the union) grown by one map
// pixel is drawn OUTER onto pixels that are all covered, by depths nearer than its own nearest by a margin.
//
// Why that is conservative: a ray from any point v of the cell to a point p of the occludee meets the plane
// at q inside the occludee's extended projection; q's pixel lies inside some occluder's extended projection,
// hence inside its projection from v: the ray meets the occluder, which lies entirely nearer along d than
// p, so before p. Occluders are solid behind their front faces (an Occluder is the promise that drawn
// geometry covers its box's faces). The margins: one map pixel around the occludee (far more than the
// rasterizer's sub-pixel snapping), and in depth 1e-6 relative plus 32 steps of a 24-bit depth buffer for
// the nearest near plane (8 steps, as the occlusion tree keeps, for rays up to 75 degrees off the view
// axis). Occluders nearer the cell than the farthest near plane are not used: the near plane clips them.
#pragma once
#include "sg/cull/PvsTable.h"

#include <vector>

namespace sg {

class PvsBuilder {
public:
    // Where each direction's projection plane lies: no occluder used may straddle it. A plane near an
    // occluder makes its extended projection tighter, but the nearer plane drops the occluders that straddle
    // it; neither choice hides more everywhere (docs/benchmarks.md), so by default both maps are drawn and
    // an entry is hidden when either hides it.
    enum class Plane : uint8_t {
        Both,           // the two below (the default: twice the maps)
        BeyondAll,      // beyond every occluder used
        BeyondLargest,  // just beyond the largest occluder seen from the cell
    };
    struct Options {
        Box region;                  // the grid's box: where the eye goes (the walkable area)
        dvec3 cellSize{5.0};         // at most this: each axis of the region is divided evenly
        uint32_t maxOccluders = 50;  // per cell and direction: the largest seen from the cell (size / distance)
        int resolution = 512;        // map pixels per side
        double maxTan = 2.0;         // the map spans directions up to atan(maxTan) (63 degrees) off its axis
        double minNear = 0.1;        // near planes the table holds for (PvsTable::minNear(), maxNear())
        double maxNear = 1.0;
        Plane plane = Plane::Both;
        std::vector<dvec3> only;  // when not empty: only the cells holding one of these points are computed
    };
    struct Stats {
        size_t cellsComputed = 0;
        uint64_t maps = 0;       // direction maps drawn
        uint64_t occluders = 0;  // extended projections drawn
        uint64_t tests = 0;      // occludee boxes tested (per direction)
        uint64_t hidden = 0;     // entries marked, summed over cells
        double ms = 0.0;
    };

    // The grid over `o.region`: cells of at most o.cellSize. Throws std::invalid_argument for an empty or
    // non-finite region or cell size.
    static PvsTable::Grid gridFor(const Options& o);
    // `scene` must be updated. Throws std::invalid_argument for bad options (resolution outside 16..8192,
    // maxTan <= 0, the near range, the grid's).
    static PvsTable build(const Scene& scene, const Options& o, Stats* stats = nullptr);
};

}  // namespace sg
