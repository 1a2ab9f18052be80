// The factory site's lighting: a sun at 40 degrees whose soft shadows and ambient occlusion are baked into
// the vertex colours of the terrain tiles and of the building models (each one's finest level, shared with its
// coarse ones) and the roofs, and the run-time light (diffuse and highlights per fragment) that goes with them.
#pragma once
#include "sg/build/VertexLightBaker.h"
#include "sg/core/DirectionalLight.h"
#include "testbed/Factory.h"

#include <string>

namespace scenes {

struct FactoryLightingStats {
    bool cached = false;    // the colours came from the cache file
    double ms = 0.0;        // wall time of the whole call (bake or read)
    uint64_t vertices = 0;  // vertices lit (the coarse levels' too)
    int targets = 0;        // meshes lit
};

// The parameters the factory is baked with: the sun from the south-west at 40 degrees elevation.
sg::VertexLightParams factoryLightParams();

// The renderer's light for the eye outside (workshop -1): the baked sun, warm, over a bluish sky; inside
// workshop k: the light of its north-light roof, from above and the north. Renderer::setLight() it
// whenever setFactoryEye() changes the workshop.
sg::DirectionalLight factoryLight(int workshop);

// Bakes (or reads from `cacheDir`, keyed by `seed`; empty: no cache) the factory's sun visibility and
// ambient occlusion into its meshes, and gives the baked geometries bakedLight copies of their materials.
// Call once, right after buildFactory(params) with the same seed, before making the Scene that draws it;
// the machines, cars and trees, whose meshes many placements share, keep their colours.
FactoryLightingStats bakeFactoryLighting(Factory& f, const std::string& cacheDir, uint32_t seed = 1996);

}  // namespace scenes
