// Whether a triangle mesh bounds solids (Mesh::closed()): the test Mesh::set() runs once per set.
// Internal header: not installed (an internal/ folder, cmake/LayerCheck.cmake).
#pragma once
#include "sg/core/Math.h"

#include <cstdint>
#include <vector>

namespace sg {

// True when, with positions welded where they are equal, every edge of the triangles is run along once in each
// direction (by two triangles), no triangle repeats a welded corner, and each connected part encloses a positive
// volume: counter-clockwise seen from outside. False for no triangles and for non-finite positions.
bool boundsSolids(const std::vector<vec3>& positions, const uint16_t* indices16, const uint32_t* indices32,
                  size_t indexCount);

}  // namespace sg
