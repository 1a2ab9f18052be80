// A named region of a map: its id and name as in the source data and its polygons (rings with holes).
#pragma once
#include <glm/vec2.hpp>

#include <string>
#include <vector>

namespace sg {

// A ring is a closed loop of points, its last point not repeating the first. Longitude/latitude in
// degrees as decoded, or projected plane coordinates (kilometres) after projection.
using GeoRing = std::vector<glm::dvec2>;

struct GeoPolygon {
    GeoRing outer;
    std::vector<GeoRing> holes;
};

struct GeoRegion {
    std::string id;    // as in the source (a number is written in decimal); empty when the source has none
    std::string name;  // properties.name, empty when absent
    std::vector<GeoPolygon> polygons;
};

}  // namespace sg
