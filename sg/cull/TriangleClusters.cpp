#include "sg/cull/TriangleClusters.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

TriangleClusters::TriangleClusters(const Mesh& mesh, uint32_t per) : per_(per), triangles_(mesh.triangleCount()) {
    if (per < 1 || per > 65536)
        throw std::invalid_argument("TriangleClusters::TriangleClusters(): " + std::to_string(per) +
                                    " triangles per cluster is not in 1..65536");
    if (!mesh.validBound()) return;
    const std::vector<vec3>& pos = mesh.positions();
    const uint32_t n = (triangles_ + per - 1) / per;
    bounds_.resize(n);
    for (uint32_t c = 0; c < n; ++c) {
        vec3 lo(HUGE_VALF), hi(-HUGE_VALF);
        const uint32_t end = std::min(triangles_, (c + 1) * per) * 3;
        for (uint32_t k = c * per * 3; k < end; ++k) {
            const vec3& p = pos[mesh.index(k)];
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        // Centre and half in float lose bits: widen the half until both ends hold, as float computes them.
        vec3 centre = 0.5f * (lo + hi), half = 0.5f * (hi - lo);
        for (int a = 0; a < 3; ++a)
            while (centre[a] - half[a] > lo[a] || centre[a] + half[a] < hi[a])
                half[a] = std::nextafter(half[a], HUGE_VALF);
        bounds_[c] = {centre, half};
        reach_ = glm::max(reach_, glm::abs(dvec3(lo)));
        reach_ = glm::max(reach_, glm::abs(dvec3(hi)));
    }
}

uint32_t TriangleClusters::keepInViewport(const dmat4& vp, const dmat4& model, std::vector<IndexRange>& out,
                                          uint64_t& tested, uint64_t& rejected) const {
    if (bounds_.empty()) {
        if (triangles_) out.push_back({0, triangles_ * 3});
        return triangles_;
    }
    const dmat4 clip = vp * model;
    auto row = [&](int r) { return dvec4(clip[0][r], clip[1][r], clip[2][r], clip[3][r]); };
    const dvec4 x = row(0), y = row(1), w = row(3);
    // The four sides as rows a with "a . (p, 1) >= 0" inside, split into xyz and the constant.
    const dvec4 side[4] = {w + x, w - x, w + y, w - y};
    const dvec3 a[4] = {dvec3(side[0]), dvec3(side[1]), dvec3(side[2]), dvec3(side[3])};
    const dvec3 absA[4] = {glm::abs(a[0]), glm::abs(a[1]), glm::abs(a[2]), glm::abs(a[3])};
    // Float rounding on the GPU (model then viewProj, both rounded to float): a few units in the last place of
    // the magnitudes summed, bounded for the whole mesh by |viewProj rows| . (|model| |p| + |translation|).
    const glm::dmat3 absM(glm::abs(dvec3(model[0])), glm::abs(dvec3(model[1])), glm::abs(dvec3(model[2])));
    const dvec3 worldMag = absM * reach_ + glm::abs(dvec3(model[3]));
    auto mag = [&](const dvec4& r) { return glm::dot(glm::abs(dvec3(r)), worldMag) + std::abs(r.w); };
    auto vpRow = [&](int r) { return dvec4(vp[0][r], vp[1][r], vp[2][r], vp[3][r]); };
    const double tol = 64.0 * double(FLT_EPSILON) * (mag(vpRow(0)) + mag(vpRow(1)) + mag(vpRow(3)));
    uint32_t kept = 0;
    const size_t before = out.size();
    const uint32_t n = uint32_t(bounds_.size());
    for (uint32_t i = 0; i < n; ++i) {
        const dvec3 c(bounds_[i].centre), h(bounds_[i].half);
        bool outside = false;
        for (int k = 0; k < 4 && !outside; ++k) outside = glm::dot(a[k], c) + side[k].w + glm::dot(absA[k], h) < -tol;
        if (outside) {
            ++rejected;
            continue;
        }
        const uint32_t first = i * per_, count = std::min(triangles_, first + per_) - first;
        kept += count;
        if (out.size() > before && out.back().first + out.back().count == first * 3)
            out.back().count += count * 3;
        else
            out.push_back({first * 3, count * 3});
    }
    tested += n;
    return kept;
}

uint32_t TriangleClusters::keepTrianglesNaive(const Mesh& mesh, const dmat4& vp, const dmat4& model) {
    const dmat4 clip = vp * model;
    const std::vector<vec3>& pos = mesh.positions();
    uint32_t kept = 0;
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
        bool behind = false;
        for (int v = 0; v < 3; ++v) {
            const dvec4 p = clip * dvec4(dvec3(pos[mesh.index(size_t(t) * 3 + size_t(v))]), 1.0);
            if (!(p.w > 0.0)) {
                behind = true;
                break;
            }
            xmin = std::min(xmin, p.x / p.w);
            xmax = std::max(xmax, p.x / p.w);
            ymin = std::min(ymin, p.y / p.w);
            ymax = std::max(ymax, p.y / p.w);
        }
        kept += behind || (xmax >= -1.0 && xmin <= 1.0 && ymax >= -1.0 && ymin <= 1.0);
    }
    return kept;
}

const TriangleClusters& TriangleClusters::Cache::get(const Mesh& mesh, uint32_t per) {
    return cache_.get(mesh, per, [&] { return std::make_unique<TriangleClusters>(mesh, per); });
}

}  // namespace sg
