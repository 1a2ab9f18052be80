// What the map's tests share: the generated map of the build tree, a point inside a region, a level entered.
#pragma once
#include "map/Atlas.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace maptest {

inline std::string generatedDir() { return SGMAP_TEST_DATA "/generated"; }
inline std::string realDir() { return SGMAP_TEST_DATA "/levels"; }
inline bool haveReal() { return std::filesystem::exists(realDir() + "/states/48.glb"); }

// A point of the scene on region `index` of the current level: the centroid of its largest upward triangle.
inline sg::dvec3 insidePoint(const sgmap::Atlas& atlas, size_t index) {
    const sgmap::Level& l = atlas.level();
    const sg::Mesh& m = *l.regions.at(index).geometries.at(0)->mesh();
    double best = -1.0;
    sg::dvec3 at(0.0);
    for (size_t t = 0; t + 2 < m.indexCount(); t += 3) {
        const sg::dvec3 a(m.positions()[m.index(t)]), b(m.positions()[m.index(t + 1)]),
            c(m.positions()[m.index(t + 2)]);
        const double up = glm::cross(b - a, c - a).z;
        if (up > best) best = up, at = (a + b + c) / 3.0;
    }
    return sg::dvec3(l.toScene * sg::dvec4(at, 1.0));
}

// Updates (waiting for the loader between frames) until the level being entered is attached or failed.
inline sgmap::Atlas::Step settle(sgmap::Atlas& atlas, uint64_t& frame) {
    sgmap::Atlas::Step s;
    for (int i = 0; i < 1000 && atlas.entering() >= 0; ++i) {
        atlas.pager().waitIdle();
        s = atlas.update({++frame, frame / 60.0});
    }
    return s;
}

inline bool enterId(sgmap::Atlas& atlas, const std::string& id, uint64_t& frame) {
    const int i = atlas.level().findId(id);
    if (i < 0 || !atlas.enter(size_t(i)).empty()) return false;
    return settle(atlas, frame).entered;
}

}  // namespace maptest
