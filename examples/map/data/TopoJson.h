// TopoJSON topologies decoded into regions: quantized, delta-encoded arcs through the transform, reversed arcs,
// Polygon and MultiPolygon geometries with holes, nested GeometryCollections, ids and properties.name.
#pragma once
#include "loaders/gltf/Gltf.h"  // sg::LoadError
#include "map/data/GeoRegion.h"

#include <map>
#include <string>
#include <vector>

namespace sg {

// Every object of the topology that is a GeometryCollection, by its key in "objects": one region per
// geometry of the collection (a nested collection's polygons form one region; points and lines have no
// polygons). Rings are in the source's coordinates (longitude, latitude), repeated consecutive points removed.
// Throws LoadError naming the file, the JSON path ("objects.states.geometries[3].arcs[0][2]") and why.
std::map<std::string, std::vector<GeoRegion>> readTopoJson(const std::string& path);
// The same from text in memory (`name` is used in messages).
std::map<std::string, std::vector<GeoRegion>> parseTopoJson(const std::string& name, const std::string& text);

}  // namespace sg
