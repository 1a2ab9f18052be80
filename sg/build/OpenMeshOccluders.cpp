// Occluders of an open mesh (meshOccluders, GeneratedOccluders.h): boxes inside it with its planar openings capped,
// or else polygons on its faces. Both work on the welded corners and on edge lists bucketed by corner (no hashing:
// generating is a step of loading, docs/benchmarks.md "Generated occluders").
//
// Polygons: adjacent triangles (sharing a welded edge) whose planes agree are merged while the union stays convex.
// Each step adds a triangle across an edge of the loop whose third corner is new, so the union is a disc of triangles
// with every corner on its boundary: its corners' angles sum to (n - 2) pi, the boundary turns once round, and a
// boundary that turns left at every corner (checked where the step changes it) is convex and covered once. The
// polygon is then exactly the union of drawn triangles.
#include "sg/build/internal/MeshOccludersParts.h"
#include "sg/scene/internal/OccluderShapes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <tuple>

namespace sg::meshocc {

Welded::Welded(const Mesh& mesh) {
    const auto& p = mesh.positions();
    struct Key {
        uint32_t x, y, z, i;
        bool operator<(const Key& o) const { return std::tie(x, y, z, i) < std::tie(o.x, o.y, o.z, o.i); }
        bool same(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    std::vector<Key> keys(p.size());
    for (size_t i = 0; i < p.size(); ++i) {
        const float c[3] = {p[i].x + 0.0f, p[i].y + 0.0f, p[i].z + 0.0f};  // + 0: -0 welds with 0
        std::memcpy(&keys[i], c, sizeof(c));
        keys[i].i = uint32_t(i);
    }
    std::sort(keys.begin(), keys.end());
    vid.resize(p.size());
    for (size_t k = 0; k < keys.size(); ++k) {
        if (k == 0 || !keys[k].same(keys[k - 1])) pos.push_back(dvec3(p[keys[k].i]));
        vid[keys[k].i] = uint32_t(pos.size() - 1);
    }
    tris.reserve(mesh.triangleCount());
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::array<uint32_t, 3> v{vid[mesh.index(3 * t)], vid[mesh.index(3 * t + 1)], vid[mesh.index(3 * t + 2)]};
        if (v[0] != v[1] && v[1] != v[2] && v[2] != v[0]) tris.push_back(v);
    }
}

namespace {

uint64_t pairKey(uint32_t a, uint32_t b) { return uint64_t(a) << 32 | b; }

// A triangle's unit normal (zero when it has no area) and its area.
struct TriFacts {
    dvec3 n;
    double area;
};

// A polygon being grown: its corners in order round it, its plane's normal and its area.
struct Poly {
    std::vector<uint32_t> loop;
    dvec3 n;
    double area;
};

std::vector<TriFacts> triangleFacts(const Welded& w) {
    const auto& vp = w.pos;
    std::vector<TriFacts> tris(w.tris.size());
    for (size_t t = 0; t < w.tris.size(); ++t) {
        const auto& v = w.tris[t];
        const dvec3 cr = glm::cross(vp[v[1]] - vp[v[0]], vp[v[2]] - vp[v[0]]);
        TriFacts& x = tris[t];
        x.area = 0.5 * glm::length(cr);
        x.n = x.area > 0.0 ? cr / (2.0 * x.area) : dvec3(0.0);
    }
    return tris;
}

// Directed edges by the corner they leave: (to, triangle), each corner's in triangle order; triangles of no area
// (against the mesh's size) have none.
struct CornerEdges {
    std::vector<uint32_t> start;
    std::vector<std::pair<uint32_t, uint32_t>> edges;

    CornerEdges(const Welded& w, const std::vector<TriFacts>& tris, double size) : start(w.pos.size() + 1, 0) {
        const size_t nt = w.tris.size();
        for (size_t t = 0; t < nt; ++t)
            if (tris[t].area > 1e-12 * size * size)
                for (uint32_t c : w.tris[t]) ++start[c + 1];
        std::partial_sum(start.begin(), start.end(), start.begin());
        edges.resize(start.back());
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (size_t t = 0; t < nt; ++t)
            if (tris[t].area > 1e-12 * size * size)
                for (int c = 0; c < 3; ++c)
                    edges[fill[w.tris[t][size_t(c)]]++] = {w.tris[t][size_t(c + 1) % 3], uint32_t(t)};
    }

    // The triangle running the directed edge (a, b), the last given when several do; -1 when none.
    int64_t across(uint32_t a, uint32_t b) const {
        for (uint32_t q = start[a + 1]; q-- > start[a];)
            if (edges[q].first == b) return int64_t(edges[q].second);
        return -1;
    }
};

// The least area a polygon keeps: a share of the bound's largest face.
double minPolygonArea(const Box& bb, const OccluderGenSettings& s) {
    const dvec3 ext = bb.max - bb.min;
    std::array<double, 3> e{ext.x, ext.y, ext.z};
    std::sort(e.begin(), e.end());
    return s.minPolygonShare * e[1] * e[2];
}

// Triangle ids, largest first (ties in id order).
std::vector<uint32_t> largestFirst(const std::vector<TriFacts>& tris) {
    std::vector<uint32_t> order(tris.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t p, uint32_t q) { return tris[p].area > tris[q].area; });
    return order;
}

// The polygon grown from triangle `seed` across the loop's edges while it stays flat and convex (the file's head);
// the triangles it takes are marked in `used`.
Poly growPolygon(uint32_t seed, const Welded& w, const std::vector<TriFacts>& tris, const CornerEdges& edges,
                 double size, double coplanar, std::vector<uint8_t>& used) {
    const auto& vp = w.pos;
    const TriFacts& st = tris[seed];
    used[seed] = 1;
    const auto& sv = w.tris[seed];
    Poly p{{sv[0], sv[1], sv[2]}, st.n, st.area};
    const dvec3 o = vp[sv[0]];
    auto left = [&](uint32_t a, uint32_t b, uint32_t c) {
        return glm::dot(glm::cross(vp[b] - vp[a], vp[c] - vp[b]), p.n) >= -eps::kRounding * size * size;
    };
    for (bool grew = true; grew;) {
        grew = false;
        for (size_t i = 0; i < p.loop.size(); ++i) {
            const size_t n = p.loop.size();
            const uint32_t u = p.loop[i], v = p.loop[(i + 1) % n];
            const int64_t f = edges.across(v, u);
            if (f < 0 || used[size_t(f)]) continue;
            const TriFacts& nb = tris[size_t(f)];
            if (glm::dot(nb.n, p.n) < 1.0 - 1e-9) continue;
            const auto& fv = w.tris[size_t(f)];
            const uint32_t x = fv[0] + fv[1] + fv[2] - u - v;  // its third corner
            if (std::abs(glm::dot(vp[x] - o, p.n)) > coplanar) continue;
            if (std::find(p.loop.begin(), p.loop.end(), x) != p.loop.end()) continue;
            // The corners the step changes: at u, at the new x, at v.
            if (!left(p.loop[(i + n - 1) % n], u, x) || !left(u, x, v) || !left(x, v, p.loop[(i + 2) % n])) continue;
            p.loop.insert(p.loop.begin() + ptrdiff_t(i + 1), x);
            p.area += nb.area;
            used[size_t(f)] = 1;
            grew = true;
        }
    }
    return p;
}

// Collinear corners (two triangles along one side) are dropped: the polygon keeps its shape.
std::vector<dvec3> turningCorners(const std::vector<uint32_t>& l, const std::vector<dvec3>& vp, double size) {
    std::vector<dvec3> v;
    for (size_t i = 0; i < l.size(); ++i) {
        const dvec3 a = vp[l[(i + l.size() - 1) % l.size()]], b = vp[l[i]], c = vp[l[(i + 1) % l.size()]];
        if (glm::length(glm::cross(b - a, c - b)) > 1e-12 * size * size) v.push_back(b);
    }
    return v;
}

// Onto the plane through their centre: the corners are off it by the positions' rounding only, and an Occluder's
// polygon must be planar to double's precision.
void flattenOntoPlane(std::vector<dvec3>& v) {
    dvec3 c(0.0), n(0.0);
    for (const dvec3& x : v) c += x / double(v.size());
    for (size_t i = 0; i < v.size(); ++i) n += glm::cross(v[i] - c, v[(i + 1) % v.size()] - c);
    n = glm::normalize(n);
    for (dvec3& x : v) x -= n * glm::dot(x - c, n);
}

}  // namespace

void openPolygons(const Mesh& mesh, const Welded& w, const OccluderGenSettings& s, MeshOccluders& out) {
    if (s.maxPolygons == 0) return;
    const Box& bb = mesh.box();
    const double size = glm::length(bb.max - bb.min);
    const std::vector<TriFacts> tris = triangleFacts(w);
    const CornerEdges edges(w, tris, size);
    const double minArea = minPolygonArea(bb, s);
    const double coplanar = occluders::flatTolerance(bb);
    std::vector<uint8_t> used(w.tris.size(), 0);
    std::vector<Poly> polys;
    for (uint32_t seed : largestFirst(tris)) {
        if (used[seed] || !(tris[seed].area > 1e-12 * size * size)) continue;
        Poly p = growPolygon(seed, w, tris, edges, size, coplanar, used);
        if (p.area >= minArea && p.area > 0.0) polys.push_back(std::move(p));
    }
    std::stable_sort(polys.begin(), polys.end(), [](const Poly& a, const Poly& b) { return a.area > b.area; });
    for (size_t k = 0; k < polys.size() && out.polygons.size() < s.maxPolygons; ++k) {
        std::vector<dvec3> v = turningCorners(polys[k].loop, w.pos, size);
        if (v.size() < 3) continue;
        flattenOntoPlane(v);
        out.polygons.push_back(std::move(v));
    }
}

namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

// An edge of the mesh by its corners, with the net count of its runs (+1 for each triangle running it from the
// lower corner to the higher, -1 back): not zero on a part's boundary.
struct Edge {
    uint64_t key;  // (lower, higher)
    int net;       // net runs
    uint32_t t;    // a triangle on it
};

// A cap edge (the boundary run back): (part, from) -> to.
using CapEdge = std::pair<uint64_t, uint32_t>;

// A boundary loop of a part, its corners in order, and the plane its cap is kept beyond.
struct Loop {
    uint32_t root;
    std::vector<uint32_t> v;
    Plane plane;
};

// Joins the triangles an edge joins into parts (`part`, a union-find over triangles) and returns the boundary edges.
std::vector<Edge> joinAtEdges(const Welded& w, std::vector<uint32_t>& part) {
    const auto& tris = w.tris;
    const size_t nt = tris.size();
    // Each triangle's edges by their lower corner: (higher corner, triangle, +1 run from the lower to the higher or -1
    // back), sorted within each corner, so an edge's runs lie together. Parts: the triangles an edge joins.
    struct Run {
        uint32_t hi, t;
        int dir;
        bool operator<(const Run& o) const { return hi < o.hi || (hi == o.hi && t < o.t); }
    };
    std::vector<uint32_t> start(w.pos.size() + 1, 0);
    for (const auto& v : tris)
        for (int c = 0; c < 3; ++c) ++start[std::min(v[size_t(c)], v[size_t(c + 1) % 3]) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<Run> runs(start.back());
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c) {
            const uint32_t a = tris[t][size_t(c)], b = tris[t][size_t(c + 1) % 3];
            runs[fill[std::min(a, b)]++] = {std::max(a, b), t, a < b ? 1 : -1};
        }
    std::vector<Edge> boundary;
    for (uint32_t lo = 0; lo + 1 < start.size(); ++lo) {
        std::sort(runs.begin() + start[lo], runs.begin() + start[lo + 1]);
        for (uint32_t q = start[lo]; q < start[lo + 1];) {
            Edge e{pairKey(lo, runs[q].hi), 0, runs[q].t};
            for (const uint32_t hi = runs[q].hi; q < start[lo + 1] && runs[q].hi == hi; ++q) {
                e.net += runs[q].dir;
                part[findRoot(part, runs[q].t)] = findRoot(part, e.t);
            }
            if (e.net != 0) boundary.push_back(e);
        }
    }
    return boundary;
}

// Cap edges (the boundary run back), per part: (part, from) -> to, sorted; a part whose boundary meets itself at
// a corner, or runs an edge twice one way, is left out.
std::vector<CapEdge> capEdges(const std::vector<Edge>& boundary, std::vector<uint32_t>& part,
                              std::vector<uint8_t>& bad) {
    std::vector<CapEdge> cap;
    for (const Edge& e : boundary) {
        const uint32_t root = findRoot(part, e.t);
        if (std::abs(e.net) > 1) {
            bad[root] = 1;
            continue;
        }
        const uint32_t lo = uint32_t(e.key >> 32), hi = uint32_t(e.key & 0xffffffffu);
        cap.push_back({pairKey(root, e.net > 0 ? hi : lo), e.net > 0 ? lo : hi});
    }
    std::sort(cap.begin(), cap.end());  // a fixed order: the same mesh gives the same shapes
    for (size_t q = 1; q < cap.size(); ++q)
        if (cap[q].first == cap[q - 1].first) bad[cap[q].first >> 32] = 1;
    return cap;
}

// Flat parts: every corner within the tolerance of the plane of the part's summed normal (zero for a closed part).
// By part root.
std::vector<uint8_t> flatParts(const Welded& w, std::vector<uint32_t>& part, const Box& bb, double diag) {
    const auto& vp = w.pos;
    const auto& tris = w.tris;
    const size_t nt = tris.size();
    std::vector<dvec3> normalSum(nt, dvec3(0.0));
    for (uint32_t t = 0; t < nt; ++t)
        normalSum[findRoot(part, t)] += glm::cross(vp[tris[t][1]] - vp[tris[t][0]], vp[tris[t][2]] - vp[tris[t][0]]);
    const double tol = occluders::flatTolerance(bb);
    std::vector<uint8_t> flat(nt, 1);
    for (uint32_t t = 0; t < nt; ++t) {
        const uint32_t r = findRoot(part, t);
        const double len = glm::length(normalSum[r]);
        if (!(len > 1e-12 * diag * diag)) {
            flat[r] = 0;
            continue;
        }
        const dvec3 n = normalSum[r] / len, o = vp[tris[r][0]];
        for (uint32_t v : tris[t])
            if (std::abs(glm::dot(vp[v] - o, n)) > tol) flat[r] = 0;
    }
    return flat;
}

// Small parts with openings (a prism on a roof, a vent) are left out: too small to hold a box of their own, their
// caps' planes would only narrow where the eye may be for the part that does.
void leaveOutSmallParts(const Welded& w, std::vector<uint32_t>& part, const std::vector<CapEdge>& cap, const Box& bb,
                        const OccluderGenSettings& s, std::vector<uint8_t>& bad) {
    std::vector<Box> partBound(w.tris.size());
    for (uint32_t t = 0; t < w.tris.size(); ++t)
        for (uint32_t v : w.tris[t]) partBound[findRoot(part, t)].expand(w.pos[v]);
    for (const auto& c : cap) {
        const uint32_t root = uint32_t(c.first >> 32);
        if (occluders::volume(partBound[root]) < s.minBoxShare * occluders::volume(bb)) bad[root] = 1;
    }
}

// The plane of loop `l`'s cap (Newell's normal points out of the solid through the cap); false when no plane holds
// the loop within the opening depth.
bool placeCapPlane(Loop& l, const std::vector<dvec3>& vp, const OccluderGenSettings& s, double diag) {
    dvec3 c(0.0), n(0.0);
    for (uint32_t v : l.v) c += vp[v] / double(l.v.size());
    for (size_t i = 0; i < l.v.size(); ++i) n += glm::cross(vp[l.v[i]] - c, vp[l.v[(i + 1) % l.v.size()]] - c);
    const double len = glm::length(n);
    double depth = 0.0;
    if (len > 0.0) {
        n /= len;
        for (uint32_t v : l.v) depth = std::max(depth, std::abs(glm::dot(vp[v] - c, n)));
    }
    if (!(len > 1e-12 * diag * diag) || depth > s.openingDepth * diag) return false;
    // Positive towards the solid, past the cap's slab by a margin over the rounding of the test.
    const double shift = depth + 1e-9 * (diag + glm::length(c));
    l.plane = Plane{-n, glm::dot(n, c) - shift};
    return true;
}

// The loops, each part's in turn, with their planes; a part with a loop that no plane closes is marked bad.
std::vector<Loop> capLoops(const std::vector<CapEdge>& cap, const std::vector<dvec3>& vp,
                           const std::vector<uint8_t>& flat, const OccluderGenSettings& s, double diag,
                           std::vector<uint8_t>& bad) {
    std::vector<Loop> loops;
    std::vector<uint8_t> walked(cap.size(), 0);
    auto capAt = [&](uint64_t key) {
        auto it = std::lower_bound(cap.begin(), cap.end(), std::make_pair(key, 0u));
        return it != cap.end() && it->first == key ? size_t(it - cap.begin()) : cap.size();
    };
    for (size_t q0 = 0; q0 < cap.size(); ++q0) {
        const uint32_t root = uint32_t(cap[q0].first >> 32);
        if (bad[root] || flat[root] || walked[q0]) continue;
        Loop l{root, {}, {}};
        // (A boundary enters each corner as often as it leaves, so the walk comes back to where it began.)
        for (size_t q = q0; q < cap.size() && !walked[q]; q = capAt(pairKey(root, cap[q].second))) {
            walked[q] = 1;
            l.v.push_back(uint32_t(cap[q].first & 0xffffffffu));
        }
        if (!placeCapPlane(l, vp, s, diag)) {
            bad[root] = 1;  // not closed by a plane
            continue;
        }
        loops.push_back(std::move(l));
    }
    return loops;
}

// The kept parts' caps: a fan of triangles over each loop, and the loop's plane.
void addCaps(const std::vector<Loop>& loops, const std::vector<uint8_t>& bad, const std::vector<dvec3>& vp,
             std::vector<Plane>& planes, std::vector<Tri>& closedTris) {
    for (const Loop& l : loops) {
        if (bad[l.root]) continue;
        planes.push_back(l.plane);
        for (size_t i = 1; i + 1 < l.v.size(); ++i) closedTris.push_back(Tri{vp[l.v[0]], vp[l.v[i]], vp[l.v[i + 1]]});
    }
}

// The kept parts' own triangles.
void addKeptTriangles(const Welded& w, std::vector<uint32_t>& part, const std::vector<uint8_t>& bad,
                      const std::vector<uint8_t>& flat, std::vector<Tri>& closedTris) {
    const auto& vp = w.pos;
    const auto& tris = w.tris;
    for (uint32_t t = 0; t < tris.size(); ++t) {
        const uint32_t r = findRoot(part, t);
        if (!bad[r] && !flat[r]) closedTris.push_back(Tri{vp[tris[t][0]], vp[tris[t][1]], vp[tris[t][2]]});
    }
}

// Whether every corner of `b` is on the positive side of every plane.
bool beyondAll(const Box& b, const std::vector<Plane>& planes) {
    bool beyond = true;
    for (const Plane& p : planes)
        for (int k = 0; k < 8 && beyond; ++k)
            beyond = p.distance(
                         dvec3(k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z)) > 0.0;
    return beyond;
}

}  // namespace

// The parts of an open mesh (triangles joined by welded edges) that bound a solid once their openings are capped: a
// closed part as it is, a part whose boundary runs in loops that each lie within `openingDepth` of a plane with a fan
// of triangles over each loop (the cap); a flat part (a quad on a wall) and any other part are left out. The boxes
// found inside are kept where they lie on the positive side of every loop's plane (each shifted past its cap's slab,
// facing the solid), and those planes are the boxes' condition (Occluder::setOpenings). Why each box is then behind
// drawn triangles: the kept parts with their caps form a closed surface (each boundary edge is run back by a cap),
// so the argument in MeshOccluders.cpp holds for it: a segment from an eye outside the bound (w = 0) to a box (w > 0)
// crosses that surface. With the eye on the positive side of every plane, the segment lies in the intersection of
// those open half-spaces (convex, holding both ends), which no cap meets: what it crosses is a drawn triangle of the
// mesh. Leaving parts out is safe for the same reason: the surface is then a subset of the drawn triangles, still
// closed.
void cappedBoxes(const Mesh& mesh, const Welded& w, const OccluderGenSettings& s, MeshOccluders& out) {
    if (!s.capOpenings || s.maxBoxes == 0) return;
    const size_t nt = w.tris.size();
    const Box& bb = mesh.box();
    const double diag = glm::length(bb.max - bb.min);
    std::vector<uint32_t> part(nt);
    std::iota(part.begin(), part.end(), 0u);
    const std::vector<Edge> boundary = joinAtEdges(w, part);
    std::vector<uint8_t> bad(nt, 0);  // by part root
    const std::vector<CapEdge> cap = capEdges(boundary, part, bad);
    const std::vector<uint8_t> flat = flatParts(w, part, bb, diag);
    leaveOutSmallParts(w, part, cap, bb, s, bad);
    const std::vector<Loop> loops = capLoops(cap, w.pos, flat, s, diag, bad);
    std::vector<Tri> closedTris;
    std::vector<Plane> planes;
    addCaps(loops, bad, w.pos, planes, closedTris);
    if (planes.size() > s.maxOpenings) return;
    addKeptTriangles(w, part, bad, flat, closedTris);
    if (closedTris.empty()) return;
    uint64_t voxels = 0;
    for (const Box& b : boxesInside(closedTris, bb, mesh.triangleCount(), s, voxels, planes))
        if (beyondAll(b, planes)) out.cappedBoxes.push_back(b);
    if (!out.cappedBoxes.empty()) out.openings = std::move(planes);
}

}  // namespace sg::meshocc
