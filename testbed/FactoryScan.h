// A simulated terrestrial laser scan of the factory site: panoramic stations along the walkthrough path and round
// the site, each ray cast through the scene and returned as a point with range noise, colour and intensity.
#pragma once
#include "sg/core/Math.h"
#include "sg/scene/Scene.h"
#include "testbed/Factory.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace scenes {

// One return of the scanner, in world coordinates (a program turns it into its file format's point).
struct ScannedPoint {
    sg::dvec3 position{0.0};
    glm::u8vec4 color{255, 255, 255, 255};
    uint16_t intensity = 0;
};

struct FactoryScanParams {
    uint64_t points = 1000000;  // returns wanted in all (the angular grid is sized for it)
    int walkStations = 12;      // along the walkthrough path's walking legs, 1.5 m above the ground
    int siteStations = 8;       // round the buildings, outside them
    double rangeNoise = 0.005;  // metres: standard deviation of the range error (Gaussian, cut at 4 deviations)
    double maxRange = 120.0;    // metres: farther surfaces give no return
    uint64_t seed = 1;          // the range noise
    int threads = 0;            // workers; 0: std::thread::hardware_concurrency()
};

struct FactoryScan {
    std::vector<sg::dvec3> stations;  // walk stations first, then site stations, in the order scanned
    int azimuthSteps = 0;             // columns of a panorama over 360 degrees
    int elevationSteps = 0;           // rows from -60 to +90 degrees, both ends included
    uint64_t rays = 0;                // fired by the scan itself
    uint64_t points = 0;              // returned (rays that met a surface within maxRange)
    uint64_t pilotRays = 0;           // fired first, on a coarse grid, to size the grid for `points`
    double seconds = 0.0;             // wall time of the pilot and the scan (not of placing the stations)
};

// Receives the points in a fixed order (station by station, column by column), whatever the thread count, on the
// calling thread; a batch may be empty.
using ScanSink = std::function<void(const std::vector<ScannedPoint>&)>;

// Scans the factory `f` whose root `scene` holds, with every workshop's interior and the outside on (what a scanner
// on the site would see); the scene is left so, updated (setFactoryEye(f, -1) brings back the defaults). Rays see
// the finest LOD levels and every node with kPickable. A colour is the hit geometry's material base colour times
// its mesh's vertex colour at the hit (textures are not sampled); an intensity falls with the angle of incidence and
// the range. The pilot's hit rate makes the returns come to about `points`. Throws std::invalid_argument naming the
// function and the value for no stations, a negative count, a range noise that is negative or not finite, a max
// range that is not positive and finite.
FactoryScan scanFactory(Factory& f, sg::Scene& scene, const FactoryScanParams& params, const ScanSink& sink);

}  // namespace scenes
