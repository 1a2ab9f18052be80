// The `city` benchmark scene and its orbit and street camera paths, as docs/scenes.md describes them.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Camera.h"

#include <cstdint>

namespace scenes {

struct CityOptions {
    int n = 100;             // N x N cells
    bool occluders = false;  // a box Occluder per building (occlusion benchmarks only)
    // Each building a feature of class `building` (id, height, floors, use) on its Transform, for picks that say
    // what they struck. Off by default: the binding is an extras block per building, which the benchmarks'
    // memory figures do not count.
    bool features = false;
};

// Building (i, j)'s properties with CityOptions::features: id i * n + j (its row), height cityHeight(i, j), a floor
// every 3 m, a use by a hash of the cell (one of kCityUses).
struct CityBuilding {
    uint32_t id = 0;
    double height = 0.0;
    uint16_t floors = 0;
    const char* use = "";
};
constexpr const char* kCityUses[4] = {"residential", "office", "retail", "industrial"};
CityBuilding cityBuilding(int n, uint32_t i, uint32_t j);

uint32_t cityHeight(uint32_t i, uint32_t j);
sg::ref_ptr<sg::Group> buildCity(const CityOptions& opt);
// Nodes per cell (7) times cells, plus tiles and the root.
uint64_t cityNodeCount(int n);

constexpr int kOrbitFrames = 120;
constexpr int kStreetFrames = 240;
// Viewport 1280x720, fov 60, near 1, far 3000; frame f of 120.
sg::Camera cityOrbitCamera(int n, int frame, int width = 1280, int height = 720);
// Viewport 1280x720, fov 60, near 0.5, far 3000; frame f of 240.
sg::Camera cityStreetCamera(int n, int frame, int width = 1280, int height = 720);

}  // namespace scenes
