#include "sg/intersect/PointBvh.h"

#include "sg/intersect/internal/IntersectPrimitives.h"

#include <algorithm>

namespace sg {

namespace {
constexpr uint32_t kLeafSize = 8;
constexpr int kStack = 128;  // median splits: the depth stays below 33, two entries a level

bool enterNode(const PointBvh::ConeFrame& f, const float* nmin, const float* nmax, double tMax, double& tNear) {
    const double mn[3] = {nmin[0], nmin[1], nmin[2]}, mx[3] = {nmax[0], nmax[1], nmax[2]};
    return f.enter(mn, mx, tMax, tNear);
}
}  // namespace

PointBvh::ConeFrame PointBvh::ConeFrame::make(const Cone& c) {
    ConeFrame f;
    f.width = c.width;
    f.slope = c.slope;
    const double det = glm::determinant(c.a), length = glm::length(c.direction);
    if (!(det != 0.0 && std::isfinite(det) && length > 0.0 && std::isfinite(c.width) && std::isfinite(c.slope)))
        return f;
    const glm::dmat3 ai = glm::inverse(c.a);
    f.o = ai * (c.origin - c.offset);
    const dvec3 d = ai * c.direction;
    f.inv = dvec3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
    f.along = glm::transpose(c.a) * (c.direction / length);
    for (int r = 0; r < 3; ++r) f.reach[r] = std::sqrt(ai[0][r] * ai[0][r] + ai[1][r] * ai[1][r] + ai[2][r] * ai[2][r]);
    f.valid = isFinite(f.o) && isFinite(f.along) && isFinite(f.reach);
    return f;
}

bool PointBvh::ConeFrame::enter(const double* mn, const double* mx, double tMax, double& tNear) const noexcept {
    double s = 0.0;  // the box's far end along the ray: the largest dot(p - o, along) over its corners
    for (int a = 0; a < 3; ++a) s += along[a] * ((along[a] > 0.0 ? mx[a] : mn[a]) - o[a]);
    const double r = radiusAt(s);
    double wmn[3], wmx[3];
    for (int a = 0; a < 3; ++a) {
        wmn[a] = mn[a] - r * reach[a];
        wmx[a] = mx[a] + r * reach[a];
    }
    return isect::slab(wmn, wmx, o, inv, tMax, tNear);
}

double PointBvh::ConeFrame::sphereReach(const dvec3& centre, double r) const {
    // Every point of the sphere is within the query's length R of the ray where R is the cone's radius at the
    // sphere's far end; R spans at most |reach| (the inverse's Frobenius norm) in this frame.
    return r + radiusAt(glm::dot(centre - o, along) + r * glm::length(along)) * glm::length(reach);
}

PointBvh::PointBvh(const Mesh& mesh) : mesh_(&mesh) {
    const auto& pos = mesh.positions();
    const bool lines = mesh.primitive() == Primitive::Lines;
    ends_ = lines ? 2 : 1;
    const uint32_t n = lines ? mesh.lineCount() : mesh.pointCount();
    auto end = [&](uint32_t k, uint32_t j) { return dvec3(pos[lines ? mesh.index(2 * size_t(k) + j) : k]); };
    std::vector<dvec3> centres(n);  // by primitive index
    prims_.reserve(n);
    for (uint32_t k = 0; k < n; ++k) {
        const dvec3 a = end(k, 0), b = end(k, ends_ - 1);
        if (!isFinite(a) || !isFinite(b)) continue;
        prims_.push_back(k);
        centres[k] = (a + b) * 0.5;
    }
    if (prims_.empty()) return;
    build(centres);
    verts_.resize(prims_.size() * ends_);
    for (size_t k = 0; k < prims_.size(); ++k)
        for (uint32_t j = 0; j < ends_; ++j) verts_[ends_ * k + j] = vec3(end(prims_[k], j));
}

// Median splits on the centres' longest axis: points are cheap to test, so a balanced tree (a bounded depth) is
// worth more than the surface-area heuristic's better splits.
void PointBvh::build(std::vector<dvec3>& centres) {
    const auto& pos = mesh_->positions();
    struct Item {
        uint32_t first, count, node;
    };
    std::vector<Item> work{{0, uint32_t(prims_.size()), 0}};
    nodes_.reserve(2 * prims_.size() / kLeafSize + 2);
    nodes_.push_back({});
    while (!work.empty()) {
        const Item it = work.back();
        work.pop_back();
        Box bound, cb;
        for (uint32_t k = it.first; k < it.first + it.count; ++k) {
            const uint32_t p = prims_[k];
            for (uint32_t j = 0; j < ends_; ++j)
                bound.expand(dvec3(pos[ends_ == 2 ? mesh_->index(2 * size_t(p) + j) : p]));
            cb.expand(centres[p]);
        }
        Node& nd = nodes_[it.node];
        isect::floatBoxOutward(bound, nd.min, nd.max);
        const dvec3 ext = cb.max - cb.min;
        const int axis = isect::longestAxis(ext);
        if (it.count <= kLeafSize || !(ext[axis] > 0.0)) {
            nd.index = it.first;
            nd.count = it.count;
            continue;
        }
        const uint32_t mid = it.first + it.count / 2;
        std::nth_element(prims_.begin() + it.first, prims_.begin() + mid, prims_.begin() + it.first + it.count,
                         [&](uint32_t a, uint32_t b) { return centres[a][axis] < centres[b][axis]; });
        const uint32_t left = uint32_t(nodes_.size());
        nodes_.push_back({});
        nodes_.push_back({});
        nodes_[it.node].index = left;
        nodes_[it.node].count = 0;
        work.push_back({mid, it.first + it.count - mid, left + 1});
        work.push_back({it.first, mid - it.first, left});
    }
}

bool PointBvh::hitPoint(const Cone& c, double tMax, const dvec3& p, ConeHit& out) noexcept {
    const double dd = glm::dot(c.direction, c.direction);
    const double t = glm::dot(p - c.origin, c.direction) / dd;
    if (!(t >= 0.0 && t <= tMax)) return false;
    const double dist = glm::length(p - (c.origin + c.direction * t));
    if (!(dist <= c.width + t * std::sqrt(dd) * c.slope)) return false;
    out.t = t;
    out.u = 0.0;
    out.point = p;
    return true;
}

bool PointBvh::hitSegment(const Cone& c, double tMax, const dvec3& p0, const dvec3& p1, ConeHit& out) noexcept {
    double t, u;
    isect::closestRaySegment(c.origin, c.direction, tMax, p0, p1, t, u);
    const dvec3 q = p0 + (p1 - p0) * u;
    const double dist = glm::length(q - (c.origin + c.direction * t));
    if (!(dist <= c.width + t * glm::length(c.direction) * c.slope)) return false;
    out.t = t;
    out.u = u;
    out.point = q;
    return true;
}

// Entry k of the leaves against the cone, exactly, in the query's frame.
bool PointBvh::leafHit(const Cone& c, uint32_t k, double tMax, ConeHit& out) const noexcept {
    const vec3* v = &verts_[size_t(ends_) * k];
    const dvec3 p0 = c.a * dvec3(v[0]) + c.offset;
    const bool hit =
        ends_ == 1 ? hitPoint(c, tMax, p0, out) : hitSegment(c, tMax, p0, c.a * dvec3(v[1]) + c.offset, out);
    if (hit) out.primitive = prims_[k];
    return hit;
}

bool PointBvh::nearest(const Cone& cone, ConeHit& out) const {
    const ConeFrame q = ConeFrame::make(cone);
    if (nodes_.empty() || !q.valid) return false;
    double best = cone.tMax;
    bool found = false;
    uint32_t stack[kStack];
    double dist[kStack];  // each entry's entry distance when pushed: skipped if a nearer hit came since
    int top = 0;
    double tn;
    if (!enterNode(q, nodes_[0].min, nodes_[0].max, best, tn)) return false;
    stack[top] = 0, dist[top++] = tn;
    while (top) {
        --top;
        if (dist[top] > best) continue;
        const Node& n = nodes_[stack[top]];
        if (n.count) {
            for (uint32_t k = n.index; k < n.index + n.count; ++k) {
                ConeHit h;
                if (leafHit(cone, k, best, h) && (!found || h.t < out.t)) {
                    best = h.t;
                    out = h;
                    found = true;
                }
            }
            continue;
        }
        SG_ASSERT(top + 2 <= kStack, "PointBvh::nearest(): traversal stack overflow");
        const uint32_t l = n.index, r = n.index + 1;
        double tl, tr;
        const bool hl = enterNode(q, nodes_[l].min, nodes_[l].max, best, tl),
                   hr = enterNode(q, nodes_[r].min, nodes_[r].max, best, tr);
        // The nearer child on top; the farther one waits.
        isect::pushChildren(stack, dist, top, l, hl, tl, r, hr, tr);
    }
    return found;
}

void PointBvh::all(const Cone& cone, std::vector<ConeHit>& out) const {
    const ConeFrame q = ConeFrame::make(cone);
    if (nodes_.empty() || !q.valid) return;
    uint32_t stack[kStack];
    int top = 0;
    stack[top++] = 0;
    double tn;
    while (top) {
        const Node& n = nodes_[stack[--top]];
        if (!enterNode(q, n.min, n.max, cone.tMax, tn)) continue;
        if (n.count) {
            for (uint32_t k = n.index; k < n.index + n.count; ++k) {
                ConeHit h;
                if (leafHit(cone, k, cone.tMax, h)) out.push_back(h);
            }
            continue;
        }
        SG_ASSERT(top + 2 <= kStack, "PointBvh::all(): traversal stack overflow");
        stack[top++] = n.index + 1;
        stack[top++] = n.index;
    }
}

size_t PointBvh::bytes() const {
    return sizeof(*this) + nodes_.capacity() * sizeof(Node) + prims_.capacity() * 4 + verts_.capacity() * sizeof(vec3);
}

}  // namespace sg
