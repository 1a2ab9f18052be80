// An equal-area map projection from longitude/latitude (degrees) to plane kilometres, with the antimeridian
// handled: a ring crossing the projection's edge is cut there, so that no polygon spans the map.
#pragma once
#include "map/data/GeoRegion.h"

#include <string>

namespace sg {

struct MapProjection {
    enum class Kind { EqualEarth, Albers };
    Kind kind = Kind::EqualEarth;
    double lon0 = 0.0, lat0 = 0.0;                       // centre (degrees); Albers: latitude of origin
    double parallel1 = 29.5, parallel2 = 45.5;           // Albers' standard parallels (degrees)
    double scale = 1.0;                                  // applied after projecting (an inset drawn smaller)
    glm::dvec2 offset{0.0};                              // then this (kilometres): where an inset is placed
    static constexpr double kEarthRadiusKm = 6371.0072;  // authalic radius: areas are the sphere's

    // Equal Earth centred on Greenwich: the world level.
    static MapProjection world();
    // Albers equal-area conic for a U.S. state or territory by its two-digit FIPS code: the conterminous
    // states on parallels 29.5/45.5 about 96W; Alaska (drawn at 0.35), Hawaii, Puerto Rico with the Virgin
    // Islands, Guam with the Northern Marianas, and American Samoa each on parallels of their own, moved as
    // insets below the conterminous states, as U.S. maps draw them. Unknown codes get the conterminous one.
    static MapProjection usState(const std::string& fips);
    // The U.S. projection that applies at a point, by the inset's area on the globe (Alaska north of 50N west
    // of 129W or east of 170E; Hawaii; Puerto Rico and the Virgin Islands; Guam and the Northern Marianas;
    // American Samoa), else the conterminous one: where a longitude/latitude lies on the U.S. level's plane.
    static MapProjection usAt(double lonDegrees, double latDegrees);

    // The point in plane kilometres; longitudes any distance from lon0 are taken modulo 360.
    glm::dvec2 project(double lonDegrees, double latDegrees) const;
    // The rings with longitudes taken relative to lon0 in [-180, 180] (degrees still), cut at the meridian
    // opposite lon0 as projectRegion does: the plane in which the map's polygons are triangulated (the source's
    // quantized coordinates keep their exact collinearities there), before each point is projected.
    GeoRegion cutAtEdge(const GeoRegion& lonLat) const;
    // Every ring projected; a ring crossing the meridian opposite lon0 is cut there into pieces (each
    // projected on its own side), and a ring around a pole is closed along the pole line.
    GeoRegion projectRegion(const GeoRegion& lonLat) const;
    // The same for a longitude already taken relative to lon0, in [-180, 180].
    glm::dvec2 projectRelative(double dLonDegrees, double latDegrees) const;
    // Plane area per true area (1 but for a scaled inset): true km^2 = plane area / areaFactor().
    double areaFactor() const { return scale * scale; }
    // "equal-earth lon0=0" or "albers lon0=-96 lat0=37.5 parallels=29.5,45.5 scale=1 offset=0,0".
    std::string describe() const;
};

}  // namespace sg
