// Random graphs (transforms with rotation and non-uniform scale, LODs, switches, billboards, instances,
// BSP groups) and random cameras of every awkward kind, for the accuracy harness and property tests.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Camera.h"

#include <cstdint>
#include <random>

namespace scenes {

// Deterministic across standard libraries: only the raw mt19937_64 stream is used.
class Rng {
public:
    explicit Rng(uint64_t seed) : g_(seed) {}
    double uniform(double a, double b) { return a + (b - a) * double(g_() >> 11) * (1.0 / 9007199254740992.0); }
    int below(int n) { return int(g_() % uint64_t(n)); }
    bool chance(double p) { return uniform(0, 1) < p; }

private:
    std::mt19937_64 g_;
};

struct RandomSceneOptions {
    int objects = 60;
    double spread = 60.0;   // objects placed in [-spread, spread]^3
    sg::dvec3 offset{0.0};  // everything moved by this (far-from-origin tests)
};
sg::ref_ptr<sg::Group> buildRandomScene(uint64_t seed, const RandomSceneOptions& opt = {});

enum class ViewKind { General, InsideObject, StraightDown, NearCutting, VeryWide, VeryNarrow, Count };
// The k-th random camera over a scene whose content lies in `bounds`; kinds cycle with k.
sg::Camera randomCamera(Rng& rng, const sg::Box& bounds, int k, int width, int height);

}  // namespace scenes
