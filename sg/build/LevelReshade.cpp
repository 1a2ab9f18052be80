#include "sg/build/LevelReshade.h"

#include "sg/intersect/MeshBvh.h"
#include "sg/intersect/internal/IntersectPrimitives.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace sg {

// The detailed level as the source of a coarse level's attributes: the point of its surface nearest a point of a
// coarse level among the triangles that face within 45 degrees of the same way (a wall's colour and texture must
// not come from the other side of it, nor from a sill's top), found through a BVH.
struct LevelReshader::Surface {
    Surface(const Mesh& fine, const ReshadeParams& params) : fine_(fine), bvh_(fine), params_(params) {}

    struct Point {
        uint32_t v[3];
        float w[3];  // barycentric weights of v
    };
    // False when no such triangle is within the search radius.
    bool nearest(const dvec3& p, const dvec3& n, Point& out) const {
        for (double r = params_.searchRadius / 8.0; r <= params_.searchRadius; r *= 2.0) {
            double best = r;
            bool found = false;
            bvh_.overlapping(Box{p - dvec3(r), p + dvec3(r)}, [&](uint32_t t) {
                dvec3 q[3];
                bvh_.triangle(t, q[0], q[1], q[2]);
                const dvec3 c = glm::cross(q[1] - q[0], q[2] - q[0]);
                if (!(glm::dot(c, n) >= 0.7 * glm::length(c) * glm::length(n))) return;
                const dvec3 x = isect::closestPointOnTriangle(p, q[0], q[1], q[2]);
                const double d = glm::length(x - p);
                if (d > best) return;
                double u = 0.0, w = 0.0;
                isect::barycentric(x, q[0], q[1], q[2], u, w);
                best = d;
                found = true;
                for (int k = 0; k < 3; ++k) out.v[k] = fine_.index(3 * size_t(t) + k);
                out.w[0] = float(1.0 - u - w), out.w[1] = float(u), out.w[2] = float(w);
            });
            if (found) return true;
        }
        return false;
    }
    template <class T>
    static T at(const std::vector<T>& a, const Point& x) {
        return x.w[0] * a[x.v[0]] + x.w[1] * a[x.v[1]] + x.w[2] * a[x.v[2]];
    }

    // How coarse level m's vertices take their colours from the detailed level: the detailed colours sampled
    // over each vertex's triangles about every sampleSpacing, on the detailed surface facing the way the
    // vertex's normal does, weighted as the coarse surface interpolates them (the sample's barycentric weight
    // and its share of the area), so that a coarse face's mean colour is that of the detailed surface under it.
    LevelColorShare shareFor(const Mesh& m) const {
        const std::vector<vec3>& mn = m.normals();
        std::vector<std::map<uint32_t, double>> acc(m.positions().size());
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            uint32_t v[3];
            dvec3 q[3];
            for (int k = 0; k < 3; ++k) q[k] = dvec3(m.positions()[v[k] = m.index(3 * size_t(t) + k)]);
            const double area = 0.5 * glm::length(glm::cross(q[1] - q[0], q[2] - q[0]));
            if (!(area > 0.0)) continue;
            const double longest =
                std::max({glm::length(q[1] - q[0]), glm::length(q[2] - q[1]), glm::length(q[0] - q[2])});
            const int k = std::clamp(int(std::ceil(longest / params_.sampleSpacing)), 1, 64);
            const double share = area / ((k + 1) * (k + 2) / 2);
            // Corners that face the same way look up the same point.
            const bool same = glm::dot(mn[v[0]], mn[v[1]]) > 0.999f && glm::dot(mn[v[0]], mn[v[2]]) > 0.999f;
            for (int i = 0; i <= k; ++i)
                for (int j = 0; i + j <= k; ++j) {
                    // Points of a triangular grid, pulled a third of a step inside so that none is a corner.
                    const double b[3] = {1.0 - (i + j + 2.0 / 3.0) / (k + 1.0), (i + 1.0 / 3.0) / (k + 1.0),
                                         (j + 1.0 / 3.0) / (k + 1.0)};
                    const dvec3 x = b[0] * q[0] + b[1] * q[1] + b[2] * q[2];
                    Point near{};
                    bool found = false;
                    for (int e = 0; e < 3; ++e) {
                        if (e == 0 || !same) found = nearest(x, dvec3(mn[v[e]]), near);
                        if (!found) continue;
                        for (int c = 0; c < 3; ++c) acc[v[e]][near.v[c]] += share * b[e] * near.w[c];
                    }
                }
        }
        LevelColorShare out;
        const std::vector<vec3>&fp = fine_.positions(), &fn = fine_.normals();
        for (size_t v = 0; v < acc.size(); ++v) {
            out.start.push_back(uint32_t(out.from.size()));
            double total = 0.0;
            for (const auto& [from, w] : acc[v]) total += w;
            if (total > 0.0) {
                for (const auto& [from, w] : acc[v])
                    if (w > 0.0) out.from.push_back(from), out.weight.push_back(float(w / total));
                continue;
            }
            // No detailed surface faces its way near its triangles: the nearest detailed vertex that does, else
            // the nearest.
            double best = std::numeric_limits<double>::infinity();
            uint32_t pick = 0;
            for (int pass = 0; pass < 2 && !std::isfinite(best); ++pass)
                for (size_t k = 0; k < fp.size(); ++k) {
                    if (pass == 0 && !(k < fn.size() && glm::dot(fn[k], mn[v]) >= 0.7f)) continue;
                    const double d = glm::length(dvec3(fp[k]) - dvec3(m.positions()[v]));
                    if (d < best) best = d, pick = uint32_t(k);
                }
            out.from.push_back(pick);
            out.weight.push_back(1.0f);
        }
        out.start.push_back(uint32_t(out.from.size()));
        return out;
    }

    // The coarse level rebuilt with a vertex per position and face orientation (see LevelReshader::reshade).
    void reshade(Mesh& m) const {
        std::vector<vec3> pos, nrm;
        std::vector<vec2> uv;
        std::vector<uint32_t> idx;
        std::map<std::pair<uint32_t, std::array<int, 3>>, uint32_t> made;
        std::vector<dvec3> nsum;
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            uint32_t v[3];
            dvec3 q[3];
            for (int k = 0; k < 3; ++k) q[k] = dvec3(m.positions()[v[k] = m.index(3 * size_t(t) + k)]);
            dvec3 n = glm::cross(q[1] - q[0], q[2] - q[0]);
            if (!(glm::length(n) > 0.0)) continue;  // a collapsed triangle covers nothing
            n = glm::normalize(n);
            const std::array<int, 3> key{int(std::lround(n.x * 64.0)), int(std::lround(n.y * 64.0)),
                                         int(std::lround(n.z * 64.0))};
            for (int k = 0; k < 3; ++k) {
                const auto it = made.emplace(std::make_pair(v[k], key), uint32_t(pos.size())).first;
                if (it->second == pos.size()) {
                    pos.push_back(m.positions()[v[k]]);
                    nsum.push_back(dvec3(0.0));
                }
                nsum[it->second] += n;
                idx.push_back(it->second);
            }
        }
        nrm.resize(pos.size());
        for (size_t v = 0; v < pos.size(); ++v) nrm[v] = vec3(glm::normalize(nsum[v]));
        if (fine_.uvs().size() == fine_.positions().size()) {
            uv.resize(pos.size());
            for (size_t v = 0; v < pos.size(); ++v) {
                Point near{};
                uv[v] = nearest(dvec3(pos[v]), dvec3(nrm[v]), near) ? at(fine_.uvs(), near) : params_.fallbackUv;
            }
        }
        m.set(std::move(pos), std::move(nrm), std::move(idx), std::move(uv));
    }

    const Mesh& fine_;
    MeshBvh bvh_;
    ReshadeParams params_;
};

LevelColorShare identityColorShare(size_t vertices) {
    LevelColorShare same;
    for (uint32_t v = 0; v <= uint32_t(vertices); ++v) same.start.push_back(v);
    same.from.assign(same.start.begin(), same.start.end() - 1);
    same.weight.assign(same.from.size(), 1.0f);
    return same;
}

LevelReshader::LevelReshader(const Mesh& fine, const ReshadeParams& params)
    : surface_(std::make_unique<Surface>(fine, params)) {}

LevelReshader::~LevelReshader() = default;

LevelColorShare LevelReshader::reshade(Mesh& coarse) const {
    surface_->reshade(coarse);
    LevelColorShare share = surface_->shareFor(coarse);
    const Mesh& fine = surface_->fine_;
    if (fine.colors().size() == fine.positions().size())
        applyColorShare(share, fine.colors(), coarse, "sg::LevelReshader::reshade()");
    return share;
}

void applyColorShare(const LevelColorShare& share, const std::vector<vec4>& fc, Mesh& m, const char* fn) {
    if (share.start.size() != m.positions().size() + 1 || share.start.back() != share.from.size() ||
        share.weight.size() != share.from.size())
        throw std::invalid_argument(std::string(fn) + ": a colour share made for another mesh");
    std::vector<vec4> col(m.positions().size(), vec4(0.0f));
    for (size_t v = 0; v < col.size(); ++v)
        for (uint32_t k = share.start[v]; k < share.start[v + 1]; ++k) {
            if (share.from[k] >= fc.size())
                throw std::invalid_argument(std::string(fn) + ": the detailed level has " + std::to_string(fc.size()) +
                                            " colours, the share reads colour " + std::to_string(share.from[k]));
            col[v] += share.weight[k] * fc[share.from[k]];
        }
    std::vector<uint32_t> idx(m.indexCount());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = m.index(i);
    m.set(m.positions(), m.normals(), std::move(idx), m.uvs(), std::move(col));
}

}  // namespace sg
