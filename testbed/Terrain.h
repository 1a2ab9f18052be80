// The `terrain` scene: a fixed-seed fractal height field as sg::buildTerrain's quadtree of LOD tiles, seen
// from the terrain culling paper's eye (docs/scenes.md).
#pragma once
#include "sg/build/TerrainBuilder.h"
#include "sg/core/Camera.h"

#include <cstdint>
#include <vector>

namespace scenes {

struct TerrainSceneParams {
    double spacing = 10.0;        // metres between samples: 1025^2 spans 10 km, 4097^2 41 km
    double roughness = 0.9;       // fractal exponent: a feature s metres across is about (s / 1 km)^this
    double reliefMetres = 150.0;  // ... times this high
    sg::TerrainParams terrain;    // tiles, levels, pixel error (for a 1024 x 768 viewport by default)
};

struct TerrainScene {
    sg::Terrain terrain;
    std::vector<float> heights;  // row-major, samplesPerSide^2, as built
    int samplesPerSide = 0;
    double spacing = 0.0;
    sg::dvec3 origin{0.0};  // of sample (0, 0): the terrain is centred on (0, 0) in x and y
    sg::Camera camera;      // terrainCamera(*this, 60)
};

// Diamond-square heights, the same for the same seed and size on every platform. Throws
// std::invalid_argument naming the function for a size that is not 2^k + 1 (3 to 8193).
std::vector<float> terrainHeights(int samplesPerSide, uint32_t seed, double spacing, double roughness = 0.9,
                                  double reliefMetres = 150.0);
TerrainScene buildTerrainScene(int samplesPerSide, uint32_t seed, const TerrainSceneParams& params = {});
// The paper's view, +Z up: its eye (0, 3000, 6000) with y up is (0, -6000, 3000) here, looking at the
// terrain's centre; near 100, far 1,000,000, vertical field of view `fovyDegrees`, 1024 x 768.
sg::Camera terrainCamera(const TerrainScene& t, double fovyDegrees, int width = 1024, int height = 768);

}  // namespace scenes
