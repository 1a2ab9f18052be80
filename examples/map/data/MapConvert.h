// The map's levels as glTF files: regions triangulated (holes included) and extruded into prisms, one Geometry
// node per region carrying its id, name, kind and area in extras; and the conversion of the source data (or a
// generated stand-in) into the world file, the U.S. file and one file per state (docs/map.md).
#pragma once
#include "loaders/gltf/Gltf.h"
#include "map/data/GeoRegion.h"
#include "map/data/MapProjection.h"
#include "nodes/Group.h"

#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace sg {

struct MapLevel {
    ref_ptr<Group> root;                                         // one Geometry per region, named after the region
    std::unordered_map<const Node*, GltfProperties> properties;  // per region node: id, name, kind, area_km2[, child]
    size_t regions = 0, emptyRegions = 0, triangles = 0;         // emptyRegions: with area but left without triangles
    // Regions whose polygons have no area in the source (a town quantized onto a line): kept, walls only, with
    // area_km2 0; "id: why" each.
    std::vector<std::string> withoutArea;
    double maxAreaError = 0.0;          // worst |triangle area - polygon area| / polygon area over the regions
    std::string worstRegion;            // its id
    std::vector<std::string> problems;  // "id: why" for each region without triangles or off by over 1e-6
};

struct MapLevelOptions {
    std::string kind = "region";                  // "country", "state", "county": each region's `kind` property
    double height = 10.0;                         // prism height (plane units, km)
    bool heightEncodesArea = false;               // heights from height/4 to height by the square root of the area
    std::map<std::string, std::string> children;  // region id -> the file of its next level (its `child`)
};

// trueAreas (km^2, one per region) go to the `area_km2` property. Regions are triangulated as given, then
// each point taken through its region's projection (MapProjection::projectRelative; the regions as
// MapProjection::cutAtEdge gives them); without projections the regions are already in the map's plane.
MapLevel buildMapLevel(const std::vector<GeoRegion>& regions, const std::vector<double>& trueAreas,
                       const MapLevelOptions& options, const std::vector<MapProjection>& projections = {});
// Writes the level as .glb with its properties; `scene` becomes the scene's extras, with "up": "+Z" and
// "units": "km" added (the map's plane is XY in kilometres, not glTF's horizontal XZ).
void writeMapLevel(const MapLevel& level, const std::string& path, const GltfProperties& scene);

struct MapConvertReport {
    size_t files = 0, regions = 0, emptyRegions = 0, triangles = 0;
    std::vector<std::string> withoutArea;  // "file: id: why", from each level
    double maxAreaError = 0.0;
    std::string worst;                  // file: region id of the worst area error
    std::vector<std::string> problems;  // "file: id: why", from each level
    double seconds = 0.0;
};

// countries-50m.json and counties-10m.json in inDir to outDir/world.glb (countries, Equal Earth),
// outDir/us.glb (states and territories, Albers with insets) and outDir/states/<FIPS>.glb (each state's
// counties, in the U.S. file's coordinates). Throws LoadError on bad input, std::runtime_error on write errors.
MapConvertReport convertMapData(const std::string& inDir, const std::string& outDir, const MapLevelOptions& base = {});
// The same layout from generated nested regions (fixed seed), for running without the source data.
MapConvertReport generateFallbackMap(const std::string& outDir, uint32_t seed = 1);

}  // namespace sg
