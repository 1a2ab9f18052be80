// Triangulation of a plane polygon with holes by ear clipping, holes bridged to the outer ring first; robust
// to the faults of real boundary data (repeated points, slivers, rings touching at a point).
#pragma once
#include "map/data/GeoRegion.h"

#include <cstdint>
#include <vector>

namespace sg {

// Triangles as index triples into the polygon's points taken in order: the outer ring, then each hole.
// Each triangle turns counter-clockwise (x right, y up) whatever the rings' own orientation.
std::vector<uint32_t> triangulatePolygon(const GeoPolygon& polygon);

// A polygon whose rings cross themselves (boundary data quantized onto a coarse grid folds back over itself
// here and there) as polygons whose rings do not: each ring is cut at its crossings, the crossing point added to
// both loops, and every loop of the outer ring becomes an outer ring (the holes go with the largest); a hole's
// loops stay holes. The area is then the region's under the nonzero rule, each loop counted positive, where the
// signed sum of the unrepaired ring would subtract a twisted loop. Polygons without crossings come back as given.
std::vector<GeoPolygon> splitSelfCrossings(const GeoPolygon& polygon);

// Signed area of a ring (positive counter-clockwise) and a polygon's area: |outer| minus |holes|.
double ringArea(const GeoRing& ring);
double polygonArea(const GeoPolygon& polygon);

}  // namespace sg
