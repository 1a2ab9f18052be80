// The factory site's baked lighting: a sun at 40 degrees with soft shadows and ambient occlusion in the
// vertex colours of the terrain tiles (baked on the finest level, shared with the coarse ones) and of both levels
// of every building model.
#pragma once
#include "sg/intersect/VertexLightBaker.h"
#include "testbed/Factory.h"

#include <string>

namespace scenes {

struct FactoryLightingStats {
    bool cached = false;    // the colours came from the cache file
    double ms = 0.0;        // wall time of the whole call (bake or read)
    uint64_t vertices = 0;  // vertices lit (the coarse terrain levels' too)
    int targets = 0;        // meshes lit
};

// The parameters the factory is baked with: the sun from the south-west at 40 degrees elevation.
sg::VertexLightParams factoryLightParams();

// Bakes (or reads from `cacheDir`, keyed by `seed`; empty: no cache) the factory's lighting into its
// meshes, and gives the lit geometries unlit copies of their materials (the colours hold all the light).
// Call once, right after buildFactory(params) with the same seed, before making the Scene that draws it;
// the machines, cars and trees, whose meshes many placements share, keep their colours.
FactoryLightingStats bakeFactoryLighting(Factory& f, const std::string& cacheDir, uint32_t seed = 1996);

}  // namespace scenes
