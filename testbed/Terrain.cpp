#include "testbed/Terrain.h"

#include "testbed/RandomScene.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace scenes {

std::vector<float> terrainHeights(int n, uint32_t seed, double spacing, double roughness, double relief) {
    if (n < 3 || n > 8193 || ((n - 1) & (n - 2)) != 0)
        throw std::invalid_argument("scenes::terrainHeights(): samplesPerSide " + std::to_string(n) +
                                    " is not 2^k + 1 (3 to 8193)");
    std::vector<float> h(size_t(n) * size_t(n), 0.0f);
    auto at = [&](int i, int j) -> float& { return h[size_t(j) * size_t(n) + size_t(i)]; };
    Rng rng(seed);
    // Displacement at a step of s samples: about (s * spacing / 1 km)^roughness * relief.
    auto amp = [&](int s) { return relief * std::pow(s * spacing / 1000.0, roughness); };
    for (int s = n - 1; s >= 2; s /= 2) {
        const int hs = s / 2;
        const double a = amp(s);
        // Diamond: the centre of each square from its corners.
        for (int j = hs; j < n; j += s)
            for (int i = hs; i < n; i += s)
                at(i, j) = float(
                    0.25 * (double(at(i - hs, j - hs)) + at(i + hs, j - hs) + at(i - hs, j + hs) + at(i + hs, j + hs)) +
                    a * rng.uniform(-1.0, 1.0));
        // Square: the edge midpoints from their (up to four) neighbours.
        for (int j = 0; j < n; j += hs)
            for (int i = ((j / hs) % 2 == 0) ? hs : 0; i < n; i += s) {
                double sum = 0.0;
                int k = 0;
                if (i >= hs) sum += at(i - hs, j), ++k;
                if (i + hs < n) sum += at(i + hs, j), ++k;
                if (j >= hs) sum += at(i, j - hs), ++k;
                if (j + hs < n) sum += at(i, j + hs), ++k;
                at(i, j) = float(sum / k + a * 0.7071 * rng.uniform(-1.0, 1.0));
            }
    }
    return h;
}

TerrainScene buildTerrainScene(int n, uint32_t seed, const TerrainSceneParams& prm) {
    TerrainScene t;
    t.heights = terrainHeights(n, seed, prm.spacing, prm.roughness, prm.reliefMetres);
    t.samplesPerSide = n;
    t.spacing = prm.spacing;
    const double half = 0.5 * (n - 1) * prm.spacing;
    t.origin = sg::dvec3(-half, -half, 0.0);
    t.terrain = sg::buildTerrain(t.heights, n, prm.spacing, t.origin, prm.terrain);
    t.camera = terrainCamera(t, 60.0);
    return t;
}

sg::Camera terrainCamera(const TerrainScene& t, double fovy, int width, int height) {
    const int c = t.samplesPerSide / 2;
    const double hc = t.heights.empty() ? 0.0 : t.heights[size_t(c) * size_t(t.samplesPerSide) + size_t(c)];
    sg::Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(fovy, double(width) / height, 100.0, 1.0e6);
    cam.setLookAt(sg::dvec3(0.0, -6000.0, 3000.0), sg::dvec3(0.0, 0.0, hc), sg::dvec3(0.0, 0.0, 1.0));
    return cam;
}

}  // namespace scenes
