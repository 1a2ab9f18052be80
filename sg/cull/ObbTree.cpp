#include "sg/cull/ObbTree.h"

#include <algorithm>
#include <cmath>

namespace sg {

namespace {
// Eigenvectors of a symmetric 3 x 3 matrix (cyclic Jacobi rotations): the columns of v.
void eigenvectors(double a[3][3], dvec3 v[3]) {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 32; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if (!(off > 1e-30)) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {  // a = J^T a J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double mkp = m[k][p], mkq = m[k][q];
                    m[k][p] = c * mkp - s * mkq;
                    m[k][q] = s * mkp + c * mkq;
                }
            }
    }
    for (int j = 0; j < 3; ++j) v[j] = dvec3(m[0][j], m[1][j], m[2][j]);
}

double volumeOf(const dvec3& half) {
    // Flat boxes compare by area, then length: a plane of triangles is not "free".
    const double s = 1e-9 * (half.x + half.y + half.z);
    return (half.x + s) * (half.y + s) * (half.z + s);
}
}  // namespace

void ObbTree::Node::corners(dvec3 out[8]) const {
    for (int k = 0; k < 8; ++k)
        out[k] = centre + axis[0] * ((k & 1) ? half.x : -half.x) + axis[1] * ((k & 2) ? half.y : -half.y) +
                 axis[2] * ((k & 4) ? half.z : -half.z);
}

ObbTree::ObbTree(const Mesh& mesh) {
    const uint32_t n = mesh.triangleCount();
    if (n == 0) return;
    pos_.reserve(mesh.positions().size());
    for (const vec3& p : mesh.positions()) {
        if (!isFinite(dvec3(p))) return;
        pos_.push_back(dvec3(p));
    }
    idx_.resize(size_t(n) * 3);
    for (size_t i = 0; i < idx_.size(); ++i) idx_[i] = mesh.index(i);
    centroid_.resize(n);
    std::vector<uint32_t> tris(n);
    for (uint32_t t = 0; t < n; ++t) {
        tris[t] = t;
        centroid_[t] = (pos_[idx_[3 * t]] + pos_[idx_[3 * t + 1]] + pos_[idx_[3 * t + 2]]) / 3.0;
    }
    nodes_.reserve(2 * (n / kLeafTriangles + 1));
    nodes_.push_back(fit(tris, 0, n));
    build(tris, 0, n, 0, 0);
    pos_.clear();
    pos_.shrink_to_fit();
    idx_.clear();
    idx_.shrink_to_fit();
    centroid_.clear();
    centroid_.shrink_to_fit();
}

ObbTree::Node ObbTree::fit(const std::vector<uint32_t>& tris, size_t begin, size_t end) const {
    // The vertices' mean and covariance: principal axes.
    dvec3 mean(0.0);
    const double count = double(end - begin) * 3.0;
    for (size_t i = begin; i < end; ++i)
        for (int k = 0; k < 3; ++k) mean += pos_[idx_[3 * tris[i] + uint32_t(k)]];
    mean /= count;
    double cov[3][3] = {};
    for (size_t i = begin; i < end; ++i)
        for (int k = 0; k < 3; ++k) {
            const dvec3 d = pos_[idx_[3 * tris[i] + uint32_t(k)]] - mean;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) cov[r][c] += d[r] * d[c];
        }
    dvec3 pca[3];
    eigenvectors(cov, pca);
    // The principal axis first (largest variance: the diagonal left by the rotations).
    const int main = cov[0][0] >= cov[1][1] && cov[0][0] >= cov[2][2] ? 0 : (cov[1][1] >= cov[2][2] ? 1 : 2);
    std::swap(pca[0], pca[main]);
    // Candidate frames: the mesh's axes; the principal axes; and the principal axis with each of the mesh's
    // axes made orthogonal to it (two equal variances leave the principal frame free to turn about the
    // first axis, and a box at 45 degrees to a square cross-section is twice as large).
    const dvec3 local[3] = {dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)};
    dvec3 frames[5][3];
    int nFrames = 0;
    auto addFrame = [&](const dvec3& a, const dvec3& b) {
        const dvec3 x = glm::normalize(a), y0 = b - x * glm::dot(x, b);
        if (!(glm::length(y0) > 1e-6) || !isFinite(x)) return;
        const dvec3 y = glm::normalize(y0);
        frames[nFrames][0] = x;
        frames[nFrames][1] = y;
        frames[nFrames][2] = glm::cross(x, y);
        ++nFrames;
    };
    addFrame(local[0], local[1]);
    addFrame(pca[0], pca[1]);
    for (const dvec3& l : local) addFrame(pca[0], l);

    Node best;
    double bestVolume = kInf;
    for (int f = 0; f < nFrames; ++f) {
        const dvec3* axes = frames[f];
        dvec3 lo(kInf), hi(-kInf);
        for (size_t i = begin; i < end; ++i)
            for (int k = 0; k < 3; ++k) {
                const dvec3& p = pos_[idx_[3 * tris[i] + uint32_t(k)]];
                const dvec3 q(glm::dot(p, axes[0]), glm::dot(p, axes[1]), glm::dot(p, axes[2]));
                lo = glm::min(lo, q);
                hi = glm::max(hi, q);
            }
        Node nd;
        for (int a = 0; a < 3; ++a) nd.axis[a] = axes[a];
        const dvec3 c = (lo + hi) * 0.5;
        nd.centre = axes[0] * c.x + axes[1] * c.y + axes[2] * c.z;
        // Outward by the rounding of the sums above: the box holds every vertex.
        const double slack = 1e-12 * (glm::length(c) + glm::length(hi - lo));
        nd.half = (hi - lo) * 0.5 + dvec3(slack);
        const double v = volumeOf(nd.half);
        if (v < bestVolume) {
            bestVolume = v;
            best = nd;
        }
    }
    best.triangles = uint32_t(end - begin);
    return best;
}

void ObbTree::build(std::vector<uint32_t>& tris, size_t begin, size_t end, uint32_t self, int level) {
    depth_ = std::max(depth_, level);
    if (end - begin <= kLeafTriangles || level >= 40) return;
    const Node nd = nodes_[self];
    const int a = nd.half.x >= nd.half.y && nd.half.x >= nd.half.z ? 0 : (nd.half.y >= nd.half.z ? 1 : 2);
    const dvec3 axis = nd.axis[a];
    const double cut = glm::dot(nd.centre, axis);
    auto along = [&](uint32_t t) { return glm::dot(centroid_[t], axis); };
    auto mid = std::partition(tris.begin() + ptrdiff_t(begin), tris.begin() + ptrdiff_t(end),
                              [&](uint32_t t) { return along(t) < cut; });
    size_t m = size_t(mid - tris.begin());
    if (m == begin || m == end) {  // all centroids on one side of the centre: halve by count along the axis
        m = (begin + end) / 2;
        std::nth_element(tris.begin() + ptrdiff_t(begin), tris.begin() + ptrdiff_t(m), tris.begin() + ptrdiff_t(end),
                         [&](uint32_t s, uint32_t t) { return along(s) < along(t); });
    }
    const uint32_t first = uint32_t(nodes_.size());
    nodes_[self].first = first;
    nodes_.push_back(fit(tris, begin, m));
    nodes_.push_back(fit(tris, m, end));
    build(tris, begin, m, first, level + 1);
    build(tris, m, end, first + 1, level + 1);
}

const ObbTree& ObbTree::Cache::get(const Mesh& mesh) {
    return cache_.get(mesh, 0, [&] { return std::make_unique<ObbTree>(mesh); });
}

}  // namespace sg
