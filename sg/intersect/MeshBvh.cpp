#include "sg/intersect/MeshBvh.h"

#include "sg/intersect/internal/IntersectPrimitives.h"

#include <algorithm>
#include <numeric>

namespace sg {

namespace {
constexpr uint32_t kLeafSize = 4;
constexpr int kBins = 12;
constexpr int kMaxSahDepth = 40;  // below this depth, median splits: the traversal stack stays bounded
constexpr int kStack = 128;

inline dvec3 inverseDir(const dvec3& d) { return dvec3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z); }

// Half a box's surface area: the heuristic's weight of a side.
double area(const Box& b) {
    if (b.empty()) return 0.0;
    const dvec3 e = b.max - b.min;
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

// The bin of a triangle's centroid along `axis`, kBins over the centroids' extent from `lo`.
struct Binner {
    const std::vector<dvec3>& centroids;
    int axis;
    double lo, scale;
    int operator()(uint32_t k) const { return std::min(kBins - 1, int((centroids[k][axis] - lo) * scale)); }
};

// The boxes' bound and the centroids' bound over [first, first + count).
void boundsOf(const std::vector<Box>& boxes, const std::vector<dvec3>& centroids, uint32_t first, uint32_t count,
              Box& bound, Box& cb) {
    for (uint32_t k = first; k < first + count; ++k) {
        bound.expand(boxes[k]);
        cb.expand(centroids[k]);
    }
}

// The last bin on the left of the cheapest binned split of [first, first + count) (bound `bound`); -1 when none
// costs less than a leaf.
int sahSplit(const Binner& bin, const std::vector<Box>& boxes, const Box& bound, uint32_t first, uint32_t count) {
    Box binBox[kBins];
    uint32_t binCount[kBins] = {};
    for (uint32_t k = first; k < first + count; ++k) {
        const int b = bin(k);
        binCount[b]++;
        binBox[b].expand(boxes[k]);
    }
    double rightArea[kBins];
    uint32_t rightCount[kBins];
    Box acc;
    uint32_t cnt = 0;
    for (int b = kBins - 1; b > 0; --b) {
        acc.expand(binBox[b]);
        cnt += binCount[b];
        rightArea[b] = area(acc);
        rightCount[b] = cnt;
    }
    double best = double(count) * area(bound);  // the cost of a leaf
    int split = -1;
    acc = Box{};
    cnt = 0;
    for (int b = 0; b < kBins - 1; ++b) {
        acc.expand(binBox[b]);
        cnt += binCount[b];
        const double cost = area(acc) * cnt + rightArea[b + 1] * rightCount[b + 1];
        if (cnt && rightCount[b + 1] && cost < best) best = cost, split = b;
    }
    return split;
}

// Moves the triangles of [first, first + count) in bins up to `split` before the others; returns where the others
// begin.
uint32_t partitionAtBin(const Binner& bin, int split, std::vector<uint32_t>& prims, std::vector<Box>& boxes,
                        std::vector<dvec3>& centroids, uint32_t first, uint32_t count) {
    uint32_t i = first, j = first + count;
    while (i < j) {
        if (bin(i) <= split) {
            ++i;
        } else {
            --j;
            std::swap(prims[i], prims[j]);
            std::swap(boxes[i], boxes[j]);
            std::swap(centroids[i], centroids[j]);
        }
    }
    return i;
}

// Orders [first, first + count) so that its first half holds the triangles with the lower centroids along `axis`.
void medianSplit(std::vector<uint32_t>& prims, std::vector<Box>& boxes, std::vector<dvec3>& centroids, uint32_t first,
                 uint32_t count, int axis) {
    std::vector<uint32_t> order(count);
    std::iota(order.begin(), order.end(), first);
    std::nth_element(order.begin(), order.begin() + count / 2, order.end(),
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    std::vector<uint32_t> p(count);
    std::vector<Box> bx(count);
    std::vector<dvec3> c(count);
    for (uint32_t k = 0; k < count; ++k) p[k] = prims[order[k]], bx[k] = boxes[order[k]], c[k] = centroids[order[k]];
    std::copy(p.begin(), p.end(), prims.begin() + first);
    std::copy(bx.begin(), bx.end(), boxes.begin() + first);
    std::copy(c.begin(), c.end(), centroids.begin() + first);
}

}  // namespace

MeshBvh::MeshBvh(const Mesh& mesh) : mesh_(&mesh) {
    const auto& pos = mesh.positions();
    const uint32_t n = mesh.triangleCount();
    std::vector<Box> boxes;
    std::vector<dvec3> centroids;
    boxes.reserve(n);
    centroids.reserve(n);
    prims_.reserve(n);
    for (uint32_t t = 0; t < n; ++t) {
        Box b;
        bool finite = true;
        for (int k = 0; k < 3; ++k) {
            const dvec3 p(pos[mesh.index(3 * t + k)]);
            finite &= isFinite(p);
            b.expand(p);
        }
        if (!finite) continue;
        prims_.push_back(t);
        boxes.push_back(b);
        centroids.push_back(b.center());
    }
    if (prims_.empty()) return;
    nodes_.reserve(2 * prims_.size() / kLeafSize + 2);
    build(0, uint32_t(prims_.size()), boxes, centroids);
    verts_.resize(prims_.size() * 3);
    for (size_t k = 0; k < prims_.size(); ++k)
        for (int j = 0; j < 3; ++j) verts_[3 * k + j] = pos[mesh.index(3 * size_t(prims_[k]) + j)];
}

// Builds the subtree over prims_[first, first + count) (boxes and centroids in the same order) with a
// binned surface-area heuristic; returns its node index.
uint32_t MeshBvh::build(uint32_t first, uint32_t count, std::vector<Box>& boxes, std::vector<dvec3>& centroids) {
    struct Item {
        uint32_t first, count, node;
        int depth;
    };
    std::vector<Item> work{{first, count, 0, 0}};
    nodes_.push_back({});
    while (!work.empty()) {
        const Item it = work.back();
        work.pop_back();
        SG_ASSERT(it.count > 0, "MeshBvh::build(): empty subtree");
        Box bound, cb;
        boundsOf(boxes, centroids, it.first, it.count, bound, cb);
        Node& nd = nodes_[it.node];
        isect::floatBoxOutward(bound, nd.min, nd.max);
        const dvec3 ext = cb.max - cb.min;
        const int axis = isect::longestAxis(ext);
        if (it.count <= kLeafSize || !(ext[axis] > 0.0)) {
            nd.index = it.first;
            nd.count = it.count;
            continue;
        }
        uint32_t mid = it.first + it.count / 2;
        bool sah = false;
        if (it.depth < kMaxSahDepth) {
            const Binner bin{centroids, axis, cb.min[axis], kBins / ext[axis]};
            const int split = sahSplit(bin, boxes, bound, it.first, it.count);
            if (split >= 0) {
                mid = partitionAtBin(bin, split, prims_, boxes, centroids, it.first, it.count);
                sah = true;
            } else if (it.count <= 16) {
                nd.index = it.first;
                nd.count = it.count;
                continue;
            }
        }
        if (!sah) medianSplit(prims_, boxes, centroids, it.first, it.count, axis);  // median on the longest axis
        SG_ASSERT(mid > it.first && mid < it.first + it.count, "MeshBvh::build(): a split left one side empty");
        SG_ASSERT(nodes_.size() + 2 <= UINT32_MAX, "MeshBvh::build(): node index overflow");
        // The two children side by side.
        const uint32_t left = uint32_t(nodes_.size()), right = left + 1;
        nodes_.push_back({});
        nodes_.push_back({});
        nodes_[it.node].index = left;
        nodes_[it.node].count = 0;
        work.push_back({mid, it.first + it.count - mid, right, it.depth + 1});
        work.push_back({it.first, mid - it.first, left, it.depth + 1});
    }
    return 0;
}

bool MeshBvh::rayTriangle(const dvec3& o, const dvec3& d, double tMax, const dvec3& p0, const dvec3& p1,
                          const dvec3& p2, RayHit& out) noexcept {
    // Woop, Benthin, Wald 2013: shear the vertices into the ray's frame (per vertex, so a vertex shared by
    // two triangles is transformed identically), then 2D edge functions. An edge shared by two triangles
    // gives the same value with opposite sign in both (a*b - c*d and c*d - a*b round alike), and zero counts
    // as inside: no ray slips between them. Needs no fused multiply-add (the build does not contract).
    const dvec3 ad = glm::abs(d);
    const int kz = ad.x >= ad.y ? (ad.x >= ad.z ? 0 : 2) : (ad.y >= ad.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0) std::swap(kx, ky);
    const double sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
    const dvec3 a = p0 - o, b = p1 - o, c = p2 - o;
    const double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    const double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    const double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
    const double u = cx * by - cy * bx;
    const double v = ax * cy - ay * cx;
    const double w = bx * ay - by * ax;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    const double det = u + v + w;
    if (!(det != 0.0)) return false;  // edge-on, or NaN
    const double t = (u * sz * a[kz] + v * sz * b[kz] + w * sz * c[kz]) / det;
    if (!(t >= 0.0 && t <= tMax)) return false;
    out.t = t;
    out.u = v / det;
    out.v = w / det;
    return true;
}

bool MeshBvh::nearest(const dvec3& o, const dvec3& d, double tMax, RayHit& out) const noexcept {
    if (nodes_.empty()) return false;
    const dvec3 inv = inverseDir(d);
    double best = tMax;
    bool found = false;
    uint32_t stack[kStack];
    double dist[kStack];  // each entry's distance when pushed: skipped if a nearer hit came since
    int top = 0;
    double tn;
    if (!isect::slab(nodes_[0].min, nodes_[0].max, o, inv, best, tn)) return false;
    stack[top] = 0, dist[top++] = tn;
    while (top) {
        --top;
        if (dist[top] > best) continue;
        const uint32_t ni = stack[top];
        const Node& n = nodes_[ni];
        if (n.count) {
            for (uint32_t k = n.index; k < n.index + n.count; ++k) {
                RayHit h;
                const vec3* v = &verts_[3 * k];
                if (rayTriangle(o, d, best, dvec3(v[0]), dvec3(v[1]), dvec3(v[2]), h)) {
                    best = h.t;
                    h.primitive = prims_[k];
                    out = h;
                    found = true;
                }
            }
            continue;
        }
        // Nearer child first; the farther one waits on the stack.
        SG_ASSERT(top + 2 <= kStack, "MeshBvh::nearest(): traversal stack overflow");
        const uint32_t l = n.index, r = n.index + 1;
        double tl, tr;
        const bool hl = isect::slab(nodes_[l].min, nodes_[l].max, o, inv, best, tl);
        const bool hr = isect::slab(nodes_[r].min, nodes_[r].max, o, inv, best, tr);
        isect::pushChildren(stack, dist, top, l, hl, tl, r, hr, tr);
    }
    return found;
}

void MeshBvh::all(const dvec3& o, const dvec3& d, double tMax, std::vector<RayHit>& out) const {
    if (nodes_.empty()) return;
    const dvec3 inv = inverseDir(d);
    uint32_t stack[kStack];
    int top = 0;
    stack[top++] = 0;
    double tn;
    while (top) {
        const uint32_t ni = stack[--top];
        const Node& n = nodes_[ni];
        if (!isect::slab(n.min, n.max, o, inv, tMax, tn)) continue;
        if (n.count) {
            for (uint32_t k = n.index; k < n.index + n.count; ++k) {
                RayHit h;
                const vec3* v = &verts_[3 * k];
                if (rayTriangle(o, d, tMax, dvec3(v[0]), dvec3(v[1]), dvec3(v[2]), h)) {
                    h.primitive = prims_[k];
                    out.push_back(h);
                }
            }
            continue;
        }
        SG_ASSERT(top + 2 <= kStack, "MeshBvh::all(): traversal stack overflow");
        stack[top++] = n.index + 1;
        stack[top++] = n.index;
    }
}

void MeshBvh::triangle(uint32_t t, dvec3& p0, dvec3& p1, dvec3& p2) const {
    SG_ASSERT(t < mesh_->triangleCount(), "MeshBvh::triangle(): primitive past the mesh's triangles");
    const auto& pos = mesh_->positions();
    p0 = dvec3(pos[mesh_->index(3 * size_t(t))]);
    p1 = dvec3(pos[mesh_->index(3 * size_t(t) + 1)]);
    p2 = dvec3(pos[mesh_->index(3 * size_t(t) + 2)]);
}

size_t MeshBvh::bytes() const {
    return sizeof(*this) + nodes_.capacity() * sizeof(Node) + prims_.capacity() * 4 + verts_.capacity() * sizeof(vec3);
}

}  // namespace sg
