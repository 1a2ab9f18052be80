// Meshes for the generated-occluder tests (closed ones wound counter-clockwise seen from outside), and the solid
// they bound worked out independently of the implementation, in double precision.
#pragma once
#include "sg/core/Mesh.h"
#include "testbed/Rng.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace occtest {

using namespace sg;

inline constexpr double kPi = 3.14159265358979323846;

// --- Meshes, built here: closed ones wound counter-clockwise seen from outside.

inline ref_ptr<Mesh> meshOf(const std::vector<dvec3>& pos, std::vector<uint32_t> idx) {
    std::vector<vec3> p;
    p.reserve(pos.size());
    for (const dvec3& v : pos) p.push_back(vec3(v));
    auto m = make<Mesh>();
    m->set(std::move(p), {}, std::move(idx));
    return m;
}

inline std::vector<uint32_t> indicesOf(const Mesh& m) {
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < m.indexCount(); ++i) idx.push_back(m.index(i));
    return idx;
}

// The mesh with every position moved by `xf` (equal positions stay equal, so a closed mesh stays closed).
inline ref_ptr<Mesh> transformed(const Mesh& m, const dmat4& xf) {
    std::vector<dvec3> pos;
    for (const vec3& p : m.positions()) pos.push_back(dvec3(xf * dvec4(dvec3(p), 1.0)));
    return meshOf(pos, indicesOf(m));
}

// The mesh without triangles [first, first + count).
inline ref_ptr<Mesh> withoutTriangles(const Mesh& m, uint32_t first, uint32_t count) {
    std::vector<uint32_t> idx = indicesOf(m);
    idx.erase(idx.begin() + 3 * first, idx.begin() + 3 * (first + count));
    std::vector<dvec3> pos;
    for (const vec3& p : m.positions()) pos.push_back(dvec3(p));
    return meshOf(pos, std::move(idx));
}

// Both meshes' triangles in one mesh.
inline ref_ptr<Mesh> merged(const Mesh& a, const Mesh& b) {
    std::vector<dvec3> pos;
    for (const vec3& p : a.positions()) pos.push_back(dvec3(p));
    for (const vec3& p : b.positions()) pos.push_back(dvec3(p));
    std::vector<uint32_t> idx = indicesOf(a);
    for (uint32_t i : indicesOf(b)) idx.push_back(i + uint32_t(a.positions().size()));
    return meshOf(pos, std::move(idx));
}

// The boundary of a union of cubes of the integer lattice (scaled by `cell`), one quad per face between a cube and
// an empty one, the lattice points shared: closed when no two cubes meet only along an edge or at a corner.
inline ref_ptr<Mesh> cellsMesh(const std::set<std::array<int, 3>>& cells, double cell = 1.0) {
    std::map<std::array<int, 3>, uint32_t> at;
    std::vector<dvec3> pos;
    std::vector<uint32_t> idx;
    auto vertex = [&](std::array<int, 3> p) {
        auto it = at.find(p);
        if (it != at.end()) return it->second;
        pos.push_back(dvec3(p[0], p[1], p[2]) * cell);
        return at[p] = uint32_t(pos.size() - 1);
    };
    for (const auto& c : cells)
        for (int a = 0; a < 3; ++a)
            for (int s : {-1, 1}) {
                std::array<int, 3> n = c;
                n[a] += s;
                if (cells.count(n)) continue;
                const int u = (a + 1) % 3, v = (a + 2) % 3;  // u x v is +axis a
                std::array<uint32_t, 4> q;
                const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                for (int k = 0; k < 4; ++k) {
                    std::array<int, 3> p = c;
                    if (s > 0) p[a] += 1;
                    p[u] += uv[k][0];
                    p[v] += uv[k][1];
                    q[k] = vertex(p);
                }
                if (s < 0) std::swap(q[1], q[3]);
                idx.insert(idx.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
            }
    return meshOf(pos, std::move(idx));
}

inline ref_ptr<Mesh> cellsWhere(int nx, int ny, int nz, const std::function<bool(int, int, int)>& in,
                                double cell = 1.0) {
    std::set<std::array<int, 3>> cells;
    for (int x = 0; x < nx; ++x)
        for (int y = 0; y < ny; ++y)
            for (int z = 0; z < nz; ++z)
                if (in(x, y, z)) cells.insert({x, y, z});
    return cellsMesh(cells, cell);
}

// An L-shaped prism: two arms 6 long and 2 wide, 2 high.
inline ref_ptr<Mesh> lPrism() {
    return cellsWhere(6, 6, 2, [](int x, int y, int) { return x < 2 || y < 2; });
}
// A U: a 6 x 6 x 3 block with a 2-wide slot cut from one side down to 2 from the other.
inline ref_ptr<Mesh> uShape() {
    return cellsWhere(6, 6, 3, [](int x, int y, int) { return !(x >= 2 && x < 4 && y >= 2); });
}
// A 6-cube with a 3-cube notch cut from one corner.
inline ref_ptr<Mesh> notchedBox() {
    return cellsWhere(6, 6, 6, [](int x, int y, int z) { return !(x >= 3 && y >= 3 && z >= 3); });
}
// Two 3-cubes 2 apart, in one mesh.
inline ref_ptr<Mesh> twoBoxes() {
    return cellsWhere(8, 3, 3, [](int x, int, int) { return x < 3 || x >= 5; });
}

// A box mesh of side 2 about the origin.
inline ref_ptr<Mesh> unitBoxMesh() { return makeBoxMesh(dvec3(-1), dvec3(1)); }

// A quad of side 2 in the plane z = 0, facing +z.
inline ref_ptr<Mesh> quadMesh() { return meshOf({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {0, 1, 2, 0, 2, 3}); }

// Torus about z: ring radius R, tube radius r, nu segments around the ring and nv around the tube.
inline ref_ptr<Mesh> torus(double R, double r, int nu, int nv) {
    std::vector<dvec3> pos;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2.0 * kPi * i / nu, v = 2.0 * kPi * j / nv;
            pos.push_back(
                dvec3((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)));
        }
    std::vector<uint32_t> idx;
    auto id = [&](int i, int j) { return uint32_t((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {  // d/du x d/dv points outward
            const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            idx.insert(idx.end(), {a, b, c, a, c, d});
        }
    return meshOf(pos, std::move(idx));
}

// A UV sphere of radius r, poles single vertices and the seam shared; `rings` bands from pole to pole. With
// `upperHalf` only the bands above the equator (rings even): a dome open at z = 0.
inline ref_ptr<Mesh> uvSphere(double r, int rings, int segments, bool upperHalf = false) {
    const int lastRing = upperHalf ? rings / 2 : rings - 1;  // rings 1..lastRing are vertex rings
    std::vector<dvec3> pos{dvec3(0, 0, r)};
    for (int j = 1; j <= lastRing; ++j)
        for (int i = 0; i < segments; ++i) {
            const double t = kPi * j / rings, p = 2.0 * kPi * i / segments;
            pos.push_back(r * dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)));
        }
    auto ring = [&](int j, int i) { return uint32_t(1 + (j - 1) * segments + (i % segments)); };
    std::vector<uint32_t> idx;
    for (int i = 0; i < segments; ++i) idx.insert(idx.end(), {0u, ring(1, i), ring(1, i + 1)});
    for (int j = 1; j < lastRing; ++j)
        for (int i = 0; i < segments; ++i) {
            const uint32_t a = ring(j, i), b = ring(j + 1, i), c = ring(j + 1, i + 1), d = ring(j, i + 1);
            idx.insert(idx.end(), {a, b, c, a, c, d});
        }
    if (!upperHalf) {
        pos.push_back(dvec3(0, 0, -r));
        const uint32_t s = uint32_t(pos.size() - 1);
        for (int i = 0; i < segments; ++i) idx.insert(idx.end(), {s, ring(lastRing, i + 1), ring(lastRing, i)});
    }
    return meshOf(pos, std::move(idx));
}

// A random rotation, uniform scale in [0.5, 4) and translation within 100 of the origin.
inline dmat4 randomPlacement(scenes::Rng& rng) {
    dvec3 axis;
    do axis = dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    while (glm::length(axis) < 0.1 || glm::length(axis) > 1.0);
    const dvec3 t(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100));
    return glm::translate(dmat4(1.0), t) * glm::rotate(dmat4(1.0), rng.uniform(0, 2 * kPi), glm::normalize(axis)) *
           glm::scale(dmat4(1.0), dvec3(rng.logUniform(0.5, 4.0)));
}

// --- The solid, independently of the implementation (double precision).

struct Tri {
    dvec3 a, b, c;
    dvec3 normal() const { return glm::cross(b - a, c - a); }  // length: twice the area
};

inline std::vector<Tri> trianglesOf(const Mesh& m) {
    std::vector<Tri> out;
    const auto& p = m.positions();
    for (uint32_t t = 0; t < m.triangleCount(); ++t)
        out.push_back({dvec3(p[m.index(3 * t)]), dvec3(p[m.index(3 * t + 1)]), dvec3(p[m.index(3 * t + 2)])});
    return out;
}

// Generalised winding number (solid angles, Van Oosterom and Strackee): an integer off the surface of a closed
// mesh, 1 inside a solid wound counter-clockwise seen from outside.
inline double windingNumber(const std::vector<Tri>& tris, const dvec3& p) {
    double sum = 0.0;
    for (const Tri& t : tris) {
        const dvec3 a = t.a - p, b = t.b - p, c = t.c - p;
        const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const double det = glm::dot(a, glm::cross(b, c));
        const double div = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
        sum += 2.0 * std::atan2(det, div);
    }
    return sum / (4.0 * kPi);
}

// Möller-Trumbore: the ray parameter of the hit, or a negative number.
inline double rayHit(const Tri& t, const dvec3& o, const dvec3& d) {
    const dvec3 e1 = t.b - t.a, e2 = t.c - t.a, pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    if (std::abs(det) < 1e-300) return -1.0;
    const dvec3 tv = o - t.a;
    const double u = glm::dot(tv, pv) / det;
    if (u < 0.0 || u > 1.0) return -1.0;
    const dvec3 qv = glm::cross(tv, e1);
    const double v = glm::dot(d, qv) / det;
    if (v < 0.0 || u + v > 1.0) return -1.0;
    return glm::dot(e2, qv) / det;
}

// The winding number at p counted along the ray from p along d: +1 for each face the ray leaves the solid
// through, -1 for each it enters through (ray parity, with the count's sign kept for nested or crossing shells).
inline int signedCrossings(const std::vector<Tri>& tris, const dvec3& p, const dvec3& d) {
    int n = 0;
    for (const Tri& t : tris)
        if (rayHit(t, p, d) > 0.0) n += glm::dot(t.normal(), d) > 0.0 ? 1 : -1;
    return n;
}

// The nearest hit along the ray, kInf for none.
inline double firstHit(const std::vector<Tri>& tris, const dvec3& o, const dvec3& d) {
    double best = kInf;
    for (const Tri& t : tris) {
        const double h = rayHit(t, o, d);
        if (h > 0.0) best = std::min(best, h);
    }
    return best;
}

inline dvec3 randomDirection(scenes::Rng& rng) {
    dvec3 d;
    do d = dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    while (glm::length(d) < 0.1 || glm::length(d) > 1.0);
    return glm::normalize(d);
}

// Separating axes (Akenine-Möller): whether the triangle meets the closed box (touching counts).
inline bool triangleMeetsBox(const Tri& t, const Box& b) {
    const dvec3 c = b.center(), h = b.halfExtent();
    const dvec3 v[3] = {t.a - c, t.b - c, t.c - c};
    const dvec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    auto separated = [&](const dvec3& axis) {
        if (glm::length(axis) == 0.0) return false;
        const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
        const double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
        return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
    };
    const dvec3 axes[3] = {dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)};
    for (const dvec3& a : axes)
        if (separated(a)) return false;
    if (separated(glm::cross(e[0], e[1]))) return false;
    for (const dvec3& a : axes)
        for (const dvec3& ed : e)
            if (separated(glm::cross(a, ed))) return false;
    return true;
}

inline double volume(const Box& b) {
    const dvec3 d = b.max - b.min;
    return d.x * d.y * d.z;
}

// Points of the box: corners, face centres, edge midpoints and `random` points inside.
inline std::vector<dvec3> samplesOf(const Box& b, scenes::Rng& rng, int random) {
    std::vector<dvec3> out;
    for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
            for (int z = 0; z < 3; ++z) out.push_back(b.min + (b.max - b.min) * dvec3(x, y, z) * 0.5);
    for (int k = 0; k < random; ++k)
        out.push_back(
            dvec3(rng.uniform(b.min.x, b.max.x), rng.uniform(b.min.y, b.max.y), rng.uniform(b.min.z, b.max.z)));
    return out;
}

// The ray parameter where the ray from o along d enters the box (o outside it).
inline double entryInto(const Box& b, const dvec3& o, const dvec3& d) {
    double t0 = -kInf, t1 = kInf;
    for (int a = 0; a < 3; ++a) {
        const double ta = (b.min[a] - o[a]) / d[a], tb = (b.max[a] - o[a]) / d[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1 ? t0 : kInf;
}

inline std::string str(const Box& b) {
    char s[200];
    std::snprintf(s, sizeof s, "[(%.9g %.9g %.9g) (%.9g %.9g %.9g)]", b.min.x, b.min.y, b.min.z, b.max.x, b.max.y,
                  b.max.z);
    return s;
}

}  // namespace occtest
