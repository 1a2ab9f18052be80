// What moves a mesh: its skin weights (joints and weights a vertex), its morph targets, and the per-joint boxes the
// cull's bound of a pose is made of.
#include "sg/core/Mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

void Mesh::setSkinWeights(std::vector<uint16_t> joints, std::vector<float> weights, int influences,
                          size_t* normalised) {
    const char* what = "Mesh::setSkinWeights()";
    if (influences != 4 && influences != 8)
        throw std::invalid_argument(std::string(what) + ": influences is " + std::to_string(influences) +
                                    ", not 4 or 8");
    const size_t n = positions_.size();
    if (n == 0) throw std::invalid_argument(std::string(what) + ": the mesh has no positions");
    const size_t want = n * size_t(influences);
    if (joints.size() != want)
        throw std::invalid_argument(std::string(what) + ": joints has " + std::to_string(joints.size()) +
                                    " elements, not " + std::to_string(want) + " (influences x positions)");
    if (weights.size() != want)
        throw std::invalid_argument(std::string(what) + ": weights has " + std::to_string(weights.size()) +
                                    " elements, not " + std::to_string(want) + " (influences x positions)");
    size_t fixed = 0;
    uint32_t maxJoint = 0;
    for (size_t v = 0; v < n; ++v) {
        float* w = &weights[v * size_t(influences)];
        uint16_t* j = &joints[v * size_t(influences)];
        double sum = 0.0;
        for (int k = 0; k < influences; ++k) {
            if (!std::isfinite(w[k]) || w[k] < 0.0f)
                throw std::invalid_argument(std::string(what) + ": weights[" +
                                            std::to_string(v * size_t(influences) + size_t(k)) + "] is " +
                                            std::to_string(w[k]) + " (negative or not finite)");
            sum += w[k];
        }
        if (sum <= 0.0) {  // no joint moves it: the first joint carries it whole
            std::fill(w, w + influences, 0.0f);
            w[0] = 1.0f;
            ++fixed;
        } else if (std::abs(sum - 1.0) > 2e-3) {  // glTF allows rounding of about this much in stored weights
            for (int k = 0; k < influences; ++k) w[k] = float(w[k] / sum);
            ++fixed;
        }
        for (int k = 0; k < influences; ++k)
            if (w[k] > 0.0f) maxJoint = std::max<uint32_t>(maxJoint, j[k]);
    }
    joints_ = std::move(joints);
    weights_ = std::move(weights);
    influences_ = influences;
    maxJoint_ = maxJoint;
    {
        std::lock_guard<std::mutex> lock(jointBoxesMutex_);
        jointBoxes_.clear();
        jointBoxesDone_.store(false, std::memory_order_release);
    }
    if (normalised) *normalised = fixed;
}

void Mesh::setMorphTargets(std::vector<MorphTarget> targets) {
    const size_t n = positions_.size();
    for (size_t t = 0; t < targets.size(); ++t) {
        auto check = [&](const char* array, size_t got) {
            if (got != 0 && got != n)
                throw std::invalid_argument("Mesh::setMorphTargets(): targets[" + std::to_string(t) + "]." + array +
                                            " has " + std::to_string(got) + " elements, positions has " +
                                            std::to_string(n));
        };
        check("positions", targets[t].positions.size());
        check("normals", targets[t].normals.size());
        check("tangents", targets[t].tangents.size());
    }
    targets_ = std::move(targets);
    std::lock_guard<std::mutex> lock(jointBoxesMutex_);
    jointBoxes_.clear();
    jointBoxesDone_.store(false, std::memory_order_release);
}

size_t Mesh::morphBytes() const {
    size_t b = 0;
    for (const MorphTarget& t : targets_)
        b += (t.positions.size() + t.normals.size() + t.tangents.size()) * sizeof(vec3);
    return b + defaultWeights.size() * sizeof(float);
}

const std::vector<Box>& Mesh::jointBoxes() const {
    if (jointBoxesDone_.load(std::memory_order_acquire)) return jointBoxes_;
    std::lock_guard<std::mutex> lock(jointBoxesMutex_);
    if (jointBoxesDone_.load(std::memory_order_relaxed)) return jointBoxes_;
    std::vector<Box> boxes;
    if (influences_ > 0) {
        boxes.assign(size_t(maxJoint_) + 1, Box{});
        const size_t k = size_t(influences_);
        for (size_t v = 0; v < positions_.size(); ++v) {
            const dvec3 p(positions_[v]);
            for (size_t i = 0; i < k; ++i)
                if (weights_[v * k + i] > 0.0f) {
                    boxes[joints_[v * k + i]].expand(p);
                }
        }
    }
    jointBoxes_ = std::move(boxes);
    jointBoxesDone_.store(true, std::memory_order_release);
    return jointBoxes_;
}

}  // namespace sg
