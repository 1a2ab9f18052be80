// Random graphs (transforms with rotation and non-uniform scale, LODs, switches, billboards, instances,
// BSP groups) and random cameras of every awkward kind, for the accuracy harness and property tests.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Camera.h"
#include "testbed/Rng.h"

#include <cstdint>

namespace scenes {

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
