// The skinned bar the posing, cull and pick tests share: a box from x = 0 to 2 (0.2 thick), vertices at x = 0, 1, 2;
// those at x = 2 follow joint 1, the others joint 0; with `blend`, those at x = 1 follow both halves each.
#pragma once
#include "sg/core/Mesh.h"

#include <cmath>
#include <vector>

namespace testutil {

inline sg::ref_ptr<sg::Mesh> skinnedBar(bool blend = false) {
    sg::ref_ptr<sg::Mesh> m = sg::makeBoxMesh(sg::dvec3(0, -0.1, -0.1), sg::dvec3(2, 0.1, 0.1), 2);
    std::vector<uint16_t> joints;
    std::vector<float> weights;
    for (const sg::vec3& p : m->positions()) {
        const bool mid = std::abs(p.x - 1.0f) < 1e-6f;
        joints.insert(joints.end(), {uint16_t(p.x > 1.5f ? 1 : 0), 1, 0, 0});
        if (blend && mid)
            weights.insert(weights.end(), {0.5f, 0.5f, 0.0f, 0.0f});
        else
            weights.insert(weights.end(), {1.0f, 0.0f, 0.0f, 0.0f});
    }
    m->setSkinWeights(std::move(joints), std::move(weights), 4);
    return m;
}

}  // namespace testutil
