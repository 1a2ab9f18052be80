#include "testbed/Factory.h"

#include "testbed/FactoryTextures.h"

#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "sg/core/Assert.h"
#include "sg/intersect/IntersectPrimitives.h"
#include "sg/intersect/MeshBvh.h"
#include "sg/lod/LodGenerator.h"
#include "sg/scene/TerrainBuilder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>

namespace scenes {

using namespace sg;

namespace {

// mt19937 is specified exactly; the standard distributions are not, so uniforms are made here.
struct Rng {
    std::mt19937 g;
    explicit Rng(uint32_t seed) : g(seed) {}
    double uniform(double a = 0.0, double b = 1.0) { return a + (b - a) * double(g() >> 8) * (1.0 / 16777216.0); }
};

using glm::ivec2;

// The pure white corner of the wall textures: parts of a building that are not wall sample it and take
// their colour from their vertices.
const vec2 kWhiteUv(kFactoryWhiteUv, kFactoryWhiteUv);

// Triangles appended one shape at a time; every triangle is wound so that it faces its intended normal.
struct MeshBuilder {
    std::vector<vec3> p, n;
    std::vector<vec2> uv;
    std::vector<vec4> c;
    std::vector<uint32_t> idx;

    uint32_t vertex(const dvec3& pos, const dvec3& nrm, const vec2& t, const vec4& col) {
        p.emplace_back(pos);
        n.emplace_back(glm::normalize(nrm));
        uv.push_back(t);
        c.push_back(col);
        return uint32_t(p.size() - 1);
    }
    void tri(uint32_t a, uint32_t b, uint32_t d, const dvec3& facing) {
        const vec3 g = glm::cross(p[b] - p[a], p[d] - p[a]);
        if (glm::dot(dvec3(g), facing) < 0.0) std::swap(b, d);
        idx.insert(idx.end(), {a, b, d});
    }
    // Corners in order around the quad; uv per corner.
    void quad(const dvec3 q[4], const dvec3& nrm, const vec2 t[4], const vec4& col) {
        uint32_t v[4];
        for (int k = 0; k < 4; ++k) v[k] = vertex(q[k], nrm, t[k], col);
        tri(v[0], v[1], v[2], nrm);
        tri(v[0], v[2], v[3], nrm);
    }
    void box(const dvec3& mn, const dvec3& mx, const vec4& col) {
        const vec2 t[4] = {kWhiteUv, kWhiteUv, kWhiteUv, kWhiteUv};
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                const int u = (axis + 1) % 3, w = (axis + 2) % 3;
                dvec3 nrm(0.0);
                nrm[axis] = side ? 1.0 : -1.0;
                dvec3 q[4];
                for (int k = 0; k < 4; ++k) {
                    q[k][axis] = side ? mx[axis] : mn[axis];
                    q[k][u] = (k == 1 || k == 2) ? mx[u] : mn[u];
                    q[k][w] = (k >= 2) ? mx[w] : mn[w];
                }
                quad(q, nrm, t, col);
            }
    }
    // A frustum from a (radius r0) to b (radius r1) with `segs` sides; a radius of 0 makes a cone tip. Caps
    // close the ends that have a radius.
    void frustum(const dvec3& a, const dvec3& b, double r0, double r1, int segs, const vec4& col) {
        const dvec3 axis = glm::normalize(b - a);
        const dvec3 helper = std::abs(axis.z) < 0.9 ? dvec3(0, 0, 1) : dvec3(1, 0, 0);
        const dvec3 e1 = glm::normalize(glm::cross(axis, helper)), e2 = glm::cross(axis, e1);
        auto dir = [&](int k) {
            const double t = 2.0 * M_PI * k / segs;
            return e1 * std::cos(t) + e2 * std::sin(t);
        };
        std::vector<uint32_t> lo, hi;
        for (int k = 0; k < segs; ++k) {
            lo.push_back(vertex(a + r0 * dir(k), dir(k), kWhiteUv, col));
            hi.push_back(vertex(b + r1 * dir(k), dir(k), kWhiteUv, col));
        }
        for (int k = 0; k < segs; ++k) {
            const int k1 = (k + 1) % segs;
            const dvec3 out = dir(k) + dir(k1);
            if (r0 > 0.0) tri(lo[k], lo[k1], hi[k], out);
            if (r1 > 0.0) tri(hi[k], lo[k1], hi[k1], out);
        }
        auto cap = [&](const dvec3& centre, double r, const dvec3& facing) {
            std::vector<uint32_t> ring;
            for (int k = 0; k < segs; ++k) ring.push_back(vertex(centre + r * dir(k), facing, kWhiteUv, col));
            for (int k = 1; k + 1 < segs; ++k) tri(ring[0], ring[k], ring[k + 1], facing);
        };
        if (r0 > 0.0) cap(a, r0, -axis);
        if (r1 > 0.0) cap(b, r1, axis);
    }
    uint32_t triangles() const { return uint32_t(idx.size() / 3); }
    ref_ptr<Mesh> build() {
        auto m = make<Mesh>();
        m->set(std::move(p), std::move(n), std::move(idx), std::move(uv), std::move(c));
        return m;
    }
};

vec4 rgb(int r, int g, int b) { return vec4(r / 255.0f, g / 255.0f, b / 255.0f, 1.0f); }

struct BuildingSpec {
    const char* kind;
    dvec3 centre;        // ground centre
    double w, d, h;      // extent along x, y, and wall height
    double storey, bay;  // window grid
    vec4 wall, roof;
    bool sawtooth;  // workshops: north-light roof prisms
    bool brick;     // brick walls (their colour in the texture) rather than rendered ones tinted by `wall`
};

// The detailed model of a building, in its frame (ground centre at the origin): a quad per wall with
// window coordinates, a roof slab with a parapet, window sills, lintels and jambs, pilasters, doors,
// roof vents (and north-light prisms on workshops).
ref_ptr<Mesh> buildingMesh(const BuildingSpec& s) {
    MeshBuilder mb;
    const double hw = s.w / 2, hd = s.d / 2, h = s.h;
    const vec4 trim = rgb(225, 222, 214), dark = rgb(70, 58, 48), grey = rgb(140, 140, 140);
    // Walls: one quad each, outward; u counts bays, v counts storeys.
    struct Wall {
        dvec3 a, b, nrm;
    };
    const Wall walls[4] = {{dvec3(-hw, -hd, 0), dvec3(hw, -hd, 0), dvec3(0, -1, 0)},
                           {dvec3(hw, -hd, 0), dvec3(hw, hd, 0), dvec3(1, 0, 0)},
                           {dvec3(hw, hd, 0), dvec3(-hw, hd, 0), dvec3(0, 1, 0)},
                           {dvec3(-hw, hd, 0), dvec3(-hw, -hd, 0), dvec3(-1, 0, 0)}};
    for (const Wall& wl : walls) {
        const double len = glm::length(wl.b - wl.a);
        const float bays = float(std::round(len / s.bay)), storeys = float(h / s.storey);
        const dvec3 q[4] = {wl.a, wl.b, wl.b + dvec3(0, 0, h), wl.a + dvec3(0, 0, h)};
        const vec2 t[4] = {vec2(0, storeys), vec2(bays, storeys), vec2(bays, 0), vec2(0, 0)};
        // v runs down the texture as z runs up: texture row 0 is the top of a storey.
        mb.quad(q, wl.nrm, t, s.brick ? vec4(1.0f) : s.wall);
        const int nb = int(bays), ns = int(std::round(storeys));
        const double bw = len / nb;
        const dvec3 along = (wl.b - wl.a) / len, out = wl.nrm;
        // Window details per bay and storey, matching the texture's window (u 0.25..0.75, v 0.3..0.8 from the
        // top of the storey).
        for (int i = 0; i < nb; ++i)
            for (int k = 0; k < ns; ++k) {
                const double u0 = (i + 0.25) * bw, u1 = (i + 0.75) * bw;
                const double z1 = (k + 1) * s.storey - 0.3 * s.storey, z0 = (k + 1) * s.storey - 0.8 * s.storey;
                auto piece = [&](double ua, double ub, double za, double zb, double depth) {
                    const dvec3 p0 = wl.a + along * ua + dvec3(0, 0, za),
                                p1 = wl.a + along * ub + dvec3(0, 0, zb) + out * depth;
                    mb.box(glm::min(p0, p1), glm::max(p0, p1), trim);
                };
                piece(u0 - 0.1, u1 + 0.1, z0 - 0.12, z0, 0.18);  // sill
                piece(u0 - 0.1, u1 + 0.1, z1, z1 + 0.1, 0.1);    // lintel
                piece(u0 - 0.08, u0, z0, z1, 0.08);              // jambs
                piece(u1, u1 + 0.08, z0, z1, 0.08);
            }
        // Pilasters between bays, and at the corners.
        for (int i = 0; i <= nb; ++i) {
            const dvec3 p0 = wl.a + along * (i * bw - 0.2),
                        p1 = wl.a + along * (i * bw + 0.2) + out * 0.15 + dvec3(0, 0, h);
            mb.box(glm::min(p0, p1), glm::max(p0, p1), s.wall * vec4(0.9f, 0.9f, 0.9f, 1.0f));
        }
    }
    // Roof slab and parapet (the slab keeps the simplified level closed; roofMesh() covers its top).
    mb.box(dvec3(-hw, -hd, h - 0.2), dvec3(hw, hd, h), s.roof);
    mb.box(dvec3(-hw, -hd, h), dvec3(hw, -hd + 0.3, h + 0.6), trim);
    mb.box(dvec3(-hw, hd - 0.3, h), dvec3(hw, hd, h + 0.6), trim);
    mb.box(dvec3(-hw, -hd, h), dvec3(-hw + 0.3, hd, h + 0.6), trim);
    mb.box(dvec3(hw - 0.3, -hd, h), dvec3(hw, hd, h + 0.6), trim);
    if (s.sawtooth) {
        // North-light prisms across the roof: a vertical glazed face towards +y, a slope towards -y.
        for (double x = -hw + 4.0; x + 4.0 <= hw; x += 6.0) {
            MeshBuilder& m = mb;
            const double y0 = -hd + 1.0, y1 = hd - 1.0, z0 = h, z1 = h + 2.5;
            for (double y = y0; y < y1 - 0.1; y += 4.0) {
                const double ya = y, yb = std::min(y + 3.5, y1);
                const dvec3 base0(x, ya, z0), base1(x + 4.0, ya, z0), top0(x, yb, z1), top1(x + 4.0, yb, z1),
                    foot0(x, yb, z0), foot1(x + 4.0, yb, z0);
                const vec2 t[4] = {kWhiteUv, kWhiteUv, kWhiteUv, kWhiteUv};
                const dvec3 slope[4] = {base0, base1, top1, top0};
                m.quad(slope, glm::cross(base1 - base0, top0 - base0), t, s.roof * vec4(0.85f, 0.85f, 0.85f, 1.0f));
                const dvec3 glass[4] = {foot0, foot1, top1, top0};
                m.quad(glass, dvec3(0, 1, 0), t, rgb(90, 115, 140));
                const uint32_t a0 = m.vertex(base0, dvec3(-1, 0, 0), kWhiteUv, s.roof),
                               a1 = m.vertex(foot0, dvec3(-1, 0, 0), kWhiteUv, s.roof),
                               a2 = m.vertex(top0, dvec3(-1, 0, 0), kWhiteUv, s.roof);
                m.tri(a0, a1, a2, dvec3(-1, 0, 0));
                const uint32_t b0 = m.vertex(base1, dvec3(1, 0, 0), kWhiteUv, s.roof),
                               b1 = m.vertex(foot1, dvec3(1, 0, 0), kWhiteUv, s.roof),
                               b2 = m.vertex(top1, dvec3(1, 0, 0), kWhiteUv, s.roof);
                m.tri(b0, b1, b2, dvec3(1, 0, 0));
            }
        }
    }
    // Roof vents along the middle.
    for (double x = -hw + 3.0; x < hw - 2.0; x += std::max(6.0, s.w / 5.0))
        mb.frustum(dvec3(x, s.sawtooth ? -hd + 0.5 : 0.0, h), dvec3(x, s.sawtooth ? -hd + 0.5 : 0.0, h + 1.2), 0.4, 0.4,
                   12, grey);
    // Doors: a recessed-looking leaf with a frame, in the middle of the south and north walls.
    for (double side : {-1.0, 1.0}) {
        const double y = side * hd, dw = s.sawtooth ? 2.5 : 1.0, dh = s.sawtooth ? 4.0 : 2.4;
        const double y0 = std::min(y, y + side * 0.12), y1 = std::max(y, y + side * 0.12);
        mb.box(dvec3(-dw, y0, 0.0), dvec3(dw, y1, dh), dark);
        const double f0 = std::min(y, y + side * 0.25), f1 = std::max(y, y + side * 0.25);
        mb.box(dvec3(-dw - 0.25, f0, 0.0), dvec3(-dw, f1, dh + 0.25), trim);
        mb.box(dvec3(dw, f0, 0.0), dvec3(dw + 0.25, f1, dh + 0.25), trim);
        mb.box(dvec3(-dw - 0.25, f0, dh), dvec3(dw + 0.25, f1, dh + 0.25), trim);
        mb.box(dvec3(-dw - 0.4, y0 - (side < 0 ? 0.8 : 0.0), 0.0), dvec3(dw + 0.4, y1 + (side > 0 ? 0.8 : 0.0), 0.15),
               grey);  // step
    }
    return mb.build();
}

// The roof of a building, in its frame: corrugated metal textured in world metres, 5 cm over the slab of
// buildingMesh() and hidden at its edges by the parapet; a grid of cells about 2.5 m wide, since the baked
// light is per vertex and the parapet's and the prisms' shadows need vertices to fall on.
ref_ptr<Mesh> roofMesh(const BuildingSpec& s) {
    MeshBuilder mb;
    const double hw = s.w / 2, hd = s.d / 2, z = s.h + 0.05;
    const int nx = std::max(1, int(std::round(s.w / 2.5))), ny = std::max(1, int(std::round(s.d / 2.5)));
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const dvec3 q(-hw + s.w * i / nx, -hd + s.d * j / ny, z);
            mb.vertex(q, dvec3(0, 0, 1), vec2(float(q.x), float(q.y)) / kFactoryRoofMetres, s.roof);
        }
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const uint32_t a = uint32_t(j * (nx + 1) + i), b = a + 1, c = b + uint32_t(nx + 1), d = c - 1;
            mb.tri(a, b, c, dvec3(0, 0, 1));
            mb.tri(a, c, d, dvec3(0, 0, 1));
        }
    return mb.build();
}

// One machine group (a making-and-packing line section), 6 m along x, 2.4 m across, on the floor at z = 0:
// a plinth, cabinets, rollers, hoppers, a motor, pipes and a control panel, of exactly `target` triangles.
ref_ptr<Mesh> machineMesh(uint32_t seed, uint32_t target) {
    Rng rng(seed);
    MeshBuilder mb;
    const vec4 body = rgb(120, 160, 140), steel = rgb(180, 185, 190), yellow = rgb(220, 180, 40),
               blue = rgb(50, 80, 150), panel = rgb(90, 95, 100), red = rgb(200, 40, 30);
    mb.box(dvec3(-3.0, -1.2, 0.0), dvec3(3.0, 1.2, 0.35), panel);
    double x = -2.9;
    while (x < 2.6) {
        const double w = rng.uniform(0.6, 1.3), hgt = rng.uniform(0.8, 1.9), dep = rng.uniform(0.8, 1.2);
        const double x1 = std::min(x + w, 2.9);
        mb.box(dvec3(x, -dep, 0.35), dvec3(x1, dep * 0.4, 0.35 + hgt), body);
        // A roller across each cabinet's top and a hopper above every other one.
        mb.frustum(dvec3((x + x1) / 2, -dep, 0.45 + hgt), dvec3((x + x1) / 2, dep * 0.4, 0.45 + hgt), 0.1, 0.1, 16,
                   steel);
        if (rng.uniform() < 0.6)
            mb.frustum(dvec3((x + x1) / 2, -0.3, 0.55 + hgt), dvec3((x + x1) / 2, -0.3, 1.2 + hgt), 0.08,
                       rng.uniform(0.25, 0.4), 14, yellow);
        x = x1 + 0.05;
    }
    // Conveyor rollers along the front edge.
    for (double rx = -2.8; rx <= 2.8; rx += 0.35)
        mb.frustum(dvec3(rx, 0.55, 0.9), dvec3(rx, 1.15, 0.9), 0.06, 0.06, 10, steel);
    mb.box(dvec3(-2.9, 0.5, 0.35), dvec3(2.9, 0.55, 0.9), body);
    mb.box(dvec3(-2.9, 1.15, 0.35), dvec3(2.9, 1.2, 0.9), body);
    // Motor and its pipes.
    mb.frustum(dvec3(2.95, -0.4, 0.8), dvec3(3.6, -0.4, 0.8), 0.35, 0.35, 24, blue);
    for (int k = 0; k < 3; ++k)
        mb.frustum(dvec3(-2.9, -1.1 + 0.15 * k, 2.4 + 0.1 * k), dvec3(2.9, -1.1 + 0.15 * k, 2.4 + 0.1 * k), 0.05, 0.05,
                   8, steel);
    // Control panel with buttons until the count is reached; single-sided placards take the last pairs.
    mb.box(dvec3(-3.6, -0.5, 0.0), dvec3(-3.1, 0.5, 1.5), panel);
    int button = 0;
    while (mb.triangles() + 12 <= target) {
        const double bz = 0.8 + 0.12 * (button % 5), by = -0.4 + 0.1 * ((button / 5) % 9);
        const double bx = -3.6 - 0.03 - 0.01 * (button / 45);
        mb.box(dvec3(bx, by, bz), dvec3(bx + 0.03, by + 0.05, bz + 0.05), button % 3 ? steel : red);
        ++button;
    }
    while (mb.triangles() + 2 <= target) {
        const double py = -1.21 - 0.001 * mb.triangles(), px = -2.5 + 0.3 * (target - mb.triangles());
        const dvec3 q[4] = {dvec3(px, py, 0.5), dvec3(px + 0.25, py, 0.5), dvec3(px + 0.25, py, 0.7),
                            dvec3(px, py, 0.7)};
        const vec2 t[4] = {kWhiteUv, kWhiteUv, kWhiteUv, kWhiteUv};
        mb.quad(q, dvec3(0, -1, 0), t, rgb(240, 240, 230));
    }
    return mb.build();
}

// The terrain's height field: heights at the (n + 1)^2 points of a grid of n x n cells over the square
// [-half, half]^2, each cell split along its (i, j)-(i+1, j+1) diagonal.
struct HeightField {
    int n = 0;
    double half = 0.0, cell = 0.0;
    std::vector<double> h;
    double at(int i, int j) const { return h[size_t(j) * size_t(n + 1) + size_t(i)]; }
    // At grid coordinates (gx, gy) in [0, n]^2: the plane of the cell's triangle that holds the point.
    double interpolate(double gx, double gy) const {
        const int i = std::min(int(gx), n - 1), j = std::min(int(gy), n - 1);
        const double u = gx - i, v = gy - j;
        const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
        return u >= v ? h00 + u * (h10 - h00) + v * (h11 - h10) : h00 + v * (h01 - h00) + u * (h11 - h01);
    }
};

// Grass, darker in the hollows, browner on the stream banks and the high ground.
vec4 grassColor(double z) {
    const float g = float(std::clamp(z / 30.0, -0.1, 1.0));
    const float bank = z < -0.3 ? 1.0f : 0.0f;
    return glm::mix(vec4(0.33f + 0.15f * g, 0.55f - 0.1f * g, 0.22f, 1.0f), vec4(0.45f, 0.38f, 0.25f, 1.0f), bank);
}

// Cells per side of a tile's levels: the full grid, then 2, 4 and 8 times coarser (fewer levels for a tile
// too small to have them all).
std::vector<int> terrainLevelCells(int per) { return sg::terrainLevelCells(per, 4); }

// Tile (ti, tj) of the terrain at one level (sg::terrainTileGrid: coarse grids stitched by fans to the
// tile's full-resolution border, so neighbours at any levels meet without cracks). Every vertex is a point of
// the height field and has the same attributes at every level.
ref_ptr<Mesh> terrainTileMesh(const HeightField& g, int ti, int tj, const TerrainTileGrid& grid) {
    const int i0 = ti * grid.per, j0 = tj * grid.per;
    std::vector<vec3> pos, nrm;
    std::vector<vec2> uvs;
    std::vector<vec4> col;
    const int N = g.n;
    for (const glm::ivec2& q : grid.points) {
        const int i = i0 + q.x, j = j0 + q.y;
        const double x = -g.half + i * g.cell, y = -g.half + j * g.cell, z = g.at(i, j);
        pos.emplace_back(x, y, z);
        const double dzx = g.at(std::min(i + 1, N), j) - g.at(std::max(i - 1, 0), j);
        const double dzy = g.at(i, std::min(j + 1, N)) - g.at(i, std::max(j - 1, 0));
        nrm.emplace_back(glm::normalize(dvec3(-dzx, -dzy, 2.0 * g.cell)));
        uvs.push_back(vec2(float(x), float(y)) / kFactoryGrassMetres);
        col.push_back(grassColor(z));
    }
    auto mesh = make<Mesh>();
    mesh->set(std::move(pos), std::move(nrm), grid.indices, std::move(uvs), std::move(col));
    return mesh;
}

void fail(const std::string& what) { throw std::invalid_argument("scenes::buildFactory(): " + what); }

// Triangles under `n` with every switch on and every LOD at its finest level: each placement counted
// (drawn; an Instance's one child is its prototype), or each distinct mesh once (stored).
struct TriangleCount {
    std::set<const Mesh*> meshes;
    uint64_t drawn = 0, stored = 0;
    void walk(Node& n) {
        if (n.kind() == NodeKind::Geometry) {
            const Mesh* m = static_cast<Geometry&>(n).mesh();
            if (!m) return;
            drawn += m->triangleCount();
            if (meshes.insert(m).second) stored += m->triangleCount();
            return;
        }
        if (n.kind() == NodeKind::LOD) {
            if (n.numChildren() > 0) walk(*n.child(0));
            return;
        }
        for (size_t i = 0; i < n.numChildren(); ++i) walk(*n.child(i));
    }
};

// A building's detailed model as the source of its coarse levels' attributes: the point of its surface nearest a
// point of a coarse level among the triangles that face within 45 degrees of the same way (a wall's colour and
// texture must not come from the other side of it, nor from a sill's top), found through a BVH.
class DetailedSurface {
public:
    explicit DetailedSurface(const Mesh& fine) : fine_(fine), bvh_(fine) {}

    struct Point {
        uint32_t v[3];
        float w[3];  // barycentric weights of v
    };
    // False when no such triangle is within 2 m.
    bool nearest(const dvec3& p, const dvec3& n, Point& out) const {
        for (double r = 0.25; r <= 2.0; r *= 2.0) {
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
    // over each vertex's triangles about every metre, on the detailed surface facing the way the vertex's
    // normal does, weighted as the coarse surface interpolates them (the sample's barycentric weight and its
    // share of the area), so that a coarse face's mean colour is that of the detailed surface under it.
    FactoryColorShare shareFor(const Mesh& m) const {
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
            const int k = std::clamp(int(std::ceil(longest)), 1, 64);
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
        FactoryColorShare out;
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

private:
    const Mesh& fine_;
    MeshBvh bvh_;
};

// A coarse level as the simplifier leaves a flat-shaded model: its triangles reuse whichever vertex each cluster
// kept, with that vertex's normal and texture coordinates, which mostly belong to a face that looks another way
// (sun and shade on the wrong walls, the window texture scattered). Rebuilt with a vertex per position and face
// orientation, its normal the faces' and its texture coordinates and colour the detailed surface's there.
void reshadeCoarseLevel(const DetailedSurface& surface, const Mesh& fine, Mesh& m) {
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
    const bool hasUv = fine.uvs().size() == fine.positions().size();
    if (hasUv) {
        uv.resize(pos.size());
        for (size_t v = 0; v < pos.size(); ++v) {
            DetailedSurface::Point near{};
            uv[v] = surface.nearest(dvec3(pos[v]), dvec3(nrm[v]), near) ? DetailedSurface::at(fine.uvs(), near)
                                                                        : vec2(kFactoryWhiteUv);
        }
    }
    m.set(std::move(pos), std::move(nrm), std::move(idx), std::move(uv));
}

// Sets m's colours from the detailed level's colours `fc` by `share`; throws naming `fn` when they do not match.
void applyColorShare(const FactoryColorShare& share, const std::vector<vec4>& fc, Mesh& m, const char* fn) {
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

}  // namespace

Factory buildFactory(const FactoryParams& prm) {
    auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
    if (!finitePositive(prm.siteSize) || prm.siteSize < 600.0)
        fail("siteSize " + std::to_string(prm.siteSize) + " must be finite and at least 600 (the yard's size)");
    if (prm.terrainCells <= 0 || prm.terrainTiles <= 0 || prm.terrainCells % prm.terrainTiles != 0)
        fail("terrainCells " + std::to_string(prm.terrainCells) + " must be a positive multiple of terrainTiles " +
             std::to_string(prm.terrainTiles));
    if (prm.machinesPerWorkshop < 0 || prm.machinesPerWorkshop > 21)
        fail("machinesPerWorkshop " + std::to_string(prm.machinesPerWorkshop) + " is not in 0..21 (three rows of 7)");
    if (prm.trees < 0) fail("trees " + std::to_string(prm.trees) + " is negative");
    if (prm.cars < 0 || prm.cars > 64)
        fail("cars " + std::to_string(prm.cars) + " is not in 0..64 (the car park's bays)");
    if (!finitePositive(prm.pixelError)) fail("pixelError " + std::to_string(prm.pixelError) + " must be positive");
    if (!(prm.fadeFraction >= 0.0 && prm.fadeFraction < 1.0))
        fail("fadeFraction " + std::to_string(prm.fadeFraction) + " is not in [0, 1)");

    Factory f;
    f.root = make<Group>();
    f.root->setName("factory");
    f.outside = make<Switch>();
    f.outside->setName("outside");
    auto outside = make<Group>();
    f.outside->addChild(outside, true);
    f.root->addChild(f.outside);
    auto occluders = make<Group>();
    occluders->setName("occluders");
    f.root->addChild(occluders);
    auto interiors = make<Group>();
    interiors->setName("interiors");
    f.root->addChild(interiors);

    const auto white = make<Material>(vec4(1.0f));
    // One material per texture, shared by every mesh that shows it: the draw batches stay per mesh.
    auto textured = [](ref_ptr<Texture> tex, float anisotropy, float specular = 0.0f, float shininess = 32.0f) {
        tex->maxAnisotropy = anisotropy;
        auto m = make<Material>(vec4(1.0f), std::move(tex));
        m->specular = specular;
        m->shininess = shininess;
        return m;
    };
    // Painted and metal surfaces catch the sun; the rest stays matt.
    auto glossy = [](float specular, float shininess) {
        auto m = make<Material>(vec4(1.0f));
        m->specular = specular;
        m->shininess = shininess;
        return m;
    };

    // --- Terrain: a flat yard (radius ~210 m) in rolling hills, a stream channel cut through both.
    Rng rng(prm.seed);
    const double ph[4] = {rng.uniform(0, 6.28), rng.uniform(0, 6.28), rng.uniform(0, 6.28), rng.uniform(0, 6.28)};
    auto streamX = [](double y) { return 175.0 + 15.0 * std::sin(y / 50.0); };
    auto hills = [ph](double x, double y) {
        const double r = std::hypot(x, y - 10.0);
        const double t = std::clamp((r - 210.0) / 130.0, 0.0, 1.0);
        const double w = t * t * (3.0 - 2.0 * t);
        const double hgt = 16.0 + 9.0 * std::sin(x / 70.0 + ph[0]) * std::cos(y / 90.0 + ph[1]) +
                           6.0 * std::sin((x + y) / 45.0 + ph[2]) + 4.0 * std::cos(x / 33.0 - y / 51.0 + ph[3]);
        return w * hgt;
    };
    auto ground = [&](double x, double y) {
        const double dx = (x - streamX(y)) / 8.0;
        const double cut = std::abs(dx) < 1.0 ? 1.8 * (1.0 - dx * dx) * (1.0 - dx * dx) : 0.0;
        return hills(x, y) - cut;
    };
    auto field = std::make_shared<HeightField>();
    field->n = prm.terrainCells;
    field->half = prm.siteSize / 2.0;
    field->cell = prm.siteSize / field->n;
    const int N = field->n;
    const double half = field->half, cell = field->cell;
    field->h.resize(size_t(N + 1) * size_t(N + 1));
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) field->h[size_t(j) * (N + 1) + i] = ground(-half + i * cell, -half + j * cell);
    // The finest level's surface: each cell split along its (i, j)-(i+1, j+1) diagonal, as the mesh is.
    f.terrainHeight = [field](double x, double y) {
        const int n = field->n;
        double gx = (x + field->half) / field->cell, gy = (y + field->half) / field->cell;
        // Vertices are stored in float: one on the edge may land a rounding step outside it.
        const double slack = 1e-5 * n;
        if (!(gx >= -slack && gy >= -slack && gx <= n + slack && gy <= n + slack)) return 0.0;
        return field->interpolate(std::clamp(gx, 0.0, double(n)), std::clamp(gy, 0.0, double(n)));
    };
    // Each tile is an LOD: the full grid, then grids 2, 4 and 8 times coarser. Level i is shown from the
    // distance where its error (vertical, against the full height field) projects to pixelError pixels
    // from the tile's nearest point: the LOD measures from the tile's centre, so its radius is added.
    f.terrain = make<Group>();
    f.terrain->setName("terrain");
    const auto grass = textured(factoryGrassTexture(prm.seed), 8.0f);
    const int per = N / prm.terrainTiles;
    for (int tj = 0; tj < prm.terrainTiles; ++tj)
        for (int ti = 0; ti < prm.terrainTiles; ++ti) {
            std::vector<ref_ptr<Mesh>> levels{terrainTileMesh(*field, ti, tj, terrainTileGrid(per, per))};
            std::vector<double> errors{0.0};
            auto height = [&](int li, int lj) { return field->at(ti * per + li, tj * per + lj); };
            for (int cells : terrainLevelCells(per)) {
                if (cells == per) continue;
                const TerrainTileGrid grid = terrainTileGrid(per, cells);
                levels.push_back(terrainTileMesh(*field, ti, tj, grid));
                // Never more accurate than a finer level: distances stay in order.
                errors.push_back(std::max(errors.back(), terrainLevelError(grid, height)));
            }
            const Box box = levels[0]->box();
            const double radius = 0.5 * glm::length(box.max - box.min);
            const float kFar = std::numeric_limits<float>::max();
            std::vector<float> from(levels.size(), 0.0f);
            for (size_t i = 1; i < levels.size(); ++i) {
                const double d = errors[i] * kDefaultPixelsPerRadian / prm.pixelError + radius;
                float v = float(d);
                if (double(v) < d) v = std::nextafter(v, kFar);  // at the switch, at most pixelError
                from[i] = v;
            }
            auto lod = make<LOD>();
            lod->setName("terrain tile");
            lod->setCenter(box.center());
            for (size_t i = 0; i < levels.size(); ++i) {
                // A level as accurate as the next coarser one is never needed: an empty range.
                const float to = i + 1 < levels.size() ? from[i + 1] : kFar;
                lod->addChild(make<Geometry>(levels[i], grass), from[i], to);
                lod->setError(i, float(errors[i]));
            }
            lod->setTransition(float(prm.fadeFraction * lod->range(0).max));
            f.terrain->addChild(lod);
        }
    outside->addChild(f.terrain);

    // --- Roads and the car park: flat quads just above the yard, asphalt in world metres, painted lines.
    {
        MeshBuilder mb;
        const vec4 road = rgb(80, 80, 84), park = rgb(92, 92, 96), paint = rgb(235, 235, 228);
        auto flat = [&](double x0, double y0, double x1, double y1, const vec4& c, double z = 0.03) {
            const dvec3 q[4] = {dvec3(x0, y0, z), dvec3(x1, y0, z), dvec3(x1, y1, z), dvec3(x0, y1, z)};
            vec2 t[4];
            for (int k = 0; k < 4; ++k) t[k] = vec2(float(q[k].x), float(q[k].y)) / kFactoryAsphaltMetres;
            mb.quad(q, dvec3(0, 0, 1), t, c);
        };
        // A road and its dashed centre line (3 m dashes, 3 m gaps, 12 cm wide).
        auto roadStrip = [&](double x0, double y0, double x1, double y1) {
            flat(x0, y0, x1, y1, road);
            const bool alongX = x1 - x0 > y1 - y0;
            const double a0 = alongX ? x0 : y0, a1 = alongX ? x1 : y1, mid = alongX ? (y0 + y1) / 2 : (x0 + x1) / 2;
            for (double a = a0 + 1.5; a + 3.0 <= a1 - 1.5; a += 6.0) {
                if (alongX)
                    flat(a, mid - 0.06, a + 3.0, mid + 0.06, paint, 0.05);
                else
                    flat(mid - 0.06, a, mid + 0.06, a + 3.0, paint, 0.05);
            }
        };
        const double bridgeX = streamX(-20.0);
        roadStrip(-160, -24, bridgeX - 10, -16);  // main road, west of the bridge
        roadStrip(bridgeX + 10, -24, 200, -16);   // and east of it, out to the hills
        roadStrip(-74, -16, -66, 100);            // between the workshop columns
        roadStrip(16, -16, 24, 100);              // east of the workshops
        roadStrip(-160, 100, 24, 108);            // north ring
        flat(95, 15, 155, 85, park);              // car park
        roadStrip(24, 46, 95, 54);                // to the car park
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k <= 16; ++k) {  // parking lines
                const double x = 100.0 + 3.0 * k, y = 22.0 + 16.0 * r;
                flat(x - 0.06, y, x + 0.06, y + 5.0, paint, 0.05);
            }
        outside->addChild(make<Geometry>(mb.build(), textured(factoryAsphaltTexture(prm.seed), 8.0f)));
    }

    // --- The stream (a water strip in its channel) and the bridge carrying the main road over it.
    {
        MeshBuilder mb;
        const vec2 t[4] = {kWhiteUv, kWhiteUv, kWhiteUv, kWhiteUv};
        for (double y = -half; y < half - 1e-9; y += 8.0) {
            const double y1 = std::min(y + 8.0, half);
            const double z0 = hills(streamX(y), y) - 0.9, z1 = hills(streamX(y1), y1) - 0.9;
            const dvec3 q[4] = {dvec3(streamX(y) - 5.5, y, z0), dvec3(streamX(y) + 5.5, y, z0),
                                dvec3(streamX(y1) + 5.5, y1, z1), dvec3(streamX(y1) - 5.5, y1, z1)};
            mb.quad(q, dvec3(0, 0, 1), t, rgb(60, 110, 160));
        }
        outside->addChild(make<Geometry>(mb.build(), white));
        MeshBuilder br;
        const double bx = streamX(-20.0);
        const vec4 concrete = rgb(175, 170, 160);
        br.box(dvec3(bx - 11, -24.5, 0.0), dvec3(bx + 11, -15.5, 0.35), concrete);  // deck
        for (double y : {-24.5, -15.8}) {
            br.box(dvec3(bx - 11, y, 0.35), dvec3(bx + 11, y + 0.3, 1.3), concrete);  // parapets
            for (double x = bx - 10; x <= bx + 10; x += 2.5)
                br.box(dvec3(x, y, 1.3), dvec3(x + 0.25, y + 0.3, 1.45), concrete);
        }
        for (double x : {bx - 9.0, bx + 9.0}) br.box(dvec3(x - 0.8, -24, -1.8), dvec3(x + 0.8, -16, 0.0), concrete);
        outside->addChild(make<Geometry>(br.build(), white));
    }

    // --- The boiler house chimney.
    {
        MeshBuilder mb;
        mb.frustum(dvec3(70, -45, 0), dvec3(70, -45, 45), 3.0, 1.8, 32, rgb(150, 80, 60));
        for (double z : {15.0, 30.0, 43.0})
            mb.frustum(dvec3(70, -45, z), dvec3(70, -45, z + 0.8), 2.2, 2.2, 32, rgb(110, 110, 110));
        outside->addChild(make<Geometry>(mb.build(), white));
    }

    // --- Buildings.
    const std::vector<BuildingSpec> specs = {
        {"workshop", dvec3(-115, 75, 0), 60, 30, 10, 5, 4, rgb(205, 205, 200), rgb(120, 125, 130), true, false},
        {"workshop", dvec3(-25, 75, 0), 60, 30, 10, 5, 4, rgb(205, 205, 200), rgb(120, 125, 130), true, false},
        {"workshop", dvec3(-115, 25, 0), 60, 30, 10, 5, 4, rgb(205, 205, 200), rgb(120, 125, 130), true, false},
        {"workshop", dvec3(-25, 25, 0), 60, 30, 10, 5, 4, rgb(205, 205, 200), rgb(120, 125, 130), true, false},
        {"auxiliary", dvec3(-130, -45, 0), 20, 15, 6, 3, 3, rgb(170, 90, 70), rgb(120, 80, 70), false, true},
        {"auxiliary", dvec3(-90, -45, 0), 20, 15, 6, 3, 3, rgb(170, 90, 70), rgb(120, 80, 70), false, true},
        {"auxiliary", dvec3(-50, -45, 0), 20, 15, 6, 3, 3, rgb(170, 90, 70), rgb(120, 80, 70), false, true},
        {"auxiliary", dvec3(-10, -45, 0), 20, 15, 6, 3, 3, rgb(170, 90, 70), rgb(120, 80, 70), false, true},
        {"auxiliary", dvec3(40, -45, 0), 20, 15, 6, 3, 3, rgb(170, 90, 70), rgb(120, 80, 70), false, true},
        {"technology", dvec3(55, 75, 0), 30, 20, 17.5, 3.5, 3, rgb(215, 200, 170), rgb(100, 100, 105), false, false},
        {"office", dvec3(60, 30, 0), 40, 16, 21, 3.5, 3, rgb(230, 228, 220), rgb(100, 100, 105), false, false},
    };
    const auto wallMat = make<Material>(vec4(1.0f), factoryWindowTexture());
    const auto brickMat = make<Material>(vec4(1.0f), factoryBrickTexture(prm.seed));
    const auto roofMat = textured(factoryRoofTexture(prm.seed), 4.0f, 0.45f, 48.0f);
    for (const BuildingSpec& s : specs) {
        FactoryBuilding b;
        b.kind = s.kind;
        b.place = make<Transform>();
        b.place->setTranslation(s.centre);
        b.lod = makeLod(buildingMesh(s), s.brick ? brickMat : wallMat, {0.25f, 0.06f}, prm.pixelError);
        {
            const Mesh& fine = *static_cast<Geometry&>(*b.lod->child(0)).mesh();
            const DetailedSurface surface(fine);
            for (size_t i = 1; i < b.lod->numChildren(); ++i) {
                Mesh* m = static_cast<Geometry&>(*b.lod->child(i)).mesh();
                if (m != static_cast<Geometry&>(*b.lod->child(i - 1)).mesh()) {
                    reshadeCoarseLevel(surface, fine, *m);
                    b.coarseColors.push_back(surface.shareFor(*m));
                    applyColorShare(b.coarseColors.back(), fine.colors(), *m, "scenes::buildFactory()");
                } else if (i > 1) {
                    b.coarseColors.push_back(b.coarseColors.back());  // the simplifier repeated the level before
                } else {
                    FactoryColorShare same;  // level 1 repeats the detailed mesh: its own colours
                    for (uint32_t v = 0; v <= uint32_t(fine.positions().size()); ++v) same.start.push_back(v);
                    same.from.assign(same.start.begin(), same.start.end() - 1);
                    same.weight.assign(same.from.size(), 1.0f);
                    b.coarseColors.push_back(std::move(same));
                }
            }
        }
        b.lod->setTransition(float(prm.fadeFraction * b.lod->range(1).min));
        b.place->addChild(b.lod);
        b.roof = make<Geometry>(roofMesh(s), roofMat);
        b.place->addChild(b.roof);
        // Inside the walls, below the roof: never larger than the building it stands for. Outside the
        // Switch, since the occlusion pass uses only occluders that are there whatever the frame.
        b.occluder = make<Occluder>();
        b.occluder->setBox(Box{s.centre + dvec3(-s.w / 2 + 0.3, -s.d / 2 + 0.3, 0.0),
                               s.centre + dvec3(s.w / 2 - 0.3, s.d / 2 - 0.3, s.h - 0.3)});
        occluders->addChild(b.occluder);
        b.box = Box{s.centre + dvec3(-s.w / 2, -s.d / 2, 0.0), s.centre + dvec3(s.w / 2, s.d / 2, s.h)};
        outside->addChild(b.place);
        f.buildings.push_back(b);
    }

    // --- Trees: axial billboards (one shared crown-and-trunk polygon per kind) around the yard and along
    // the north road.
    {
        auto treeMat = make<Material>(vec4(1.0f), factoryTreeTexture(prm.seed));
        treeMat->alphaCutoff = 0.5f;  // cut at the texture outline: no fringe where filtering reaches alpha 0
        ref_ptr<Mesh> kinds[2];
        for (int k = 0; k < 2; ++k) {
            const double hgt = k ? 11.0 : 7.5, wid = hgt * 0.75;
            MeshBuilder mb;
            const dvec3 facing(0, -1, 0);
            auto at = [&](double u, double v) {  // texture coordinates -> billboard plane (faces -y)
                return dvec3((u - 0.5) * wid, 0.0, (1.0 - v) * hgt);
            };
            const vec4 c(1.0f);
            // Crown: a 12-sided fan inside the texture's ellipse; trunk: a quad inside the texture's trunk.
            const uint32_t centre = mb.vertex(at(0.5, 0.4), facing, vec2(0.5f, 0.4f), c);
            std::vector<uint32_t> ring;
            for (int s = 0; s < 12; ++s) {
                const double a = 2.0 * M_PI * s / 12;
                const double u = 0.5 + 0.43 * std::cos(a), v = 0.4 + 0.38 * std::sin(a);
                ring.push_back(mb.vertex(at(u, v), facing, vec2(float(u), float(v)), c));
            }
            for (int s = 0; s < 12; ++s) mb.tri(centre, ring[size_t(s)], ring[size_t((s + 1) % 12)], facing);
            const double tu[4] = {0.45, 0.55, 0.55, 0.45}, tv[4] = {1.0, 1.0, 0.7, 0.7};
            dvec3 q[4];
            vec2 t[4];
            for (int s = 0; s < 4; ++s) q[s] = at(tu[s], tv[s]), t[s] = vec2(float(tu[s]), float(tv[s]));
            mb.quad(q, facing, t, c);
            kinds[k] = mb.build();
        }
        auto plant = [&](double x, double y, int kind) {
            auto t = make<Transform>();
            t->setTranslation(dvec3(x, y, f.terrainHeight(x, y) - 0.2));
            auto bb = make<Billboard>();
            bb->setMode(Billboard::Mode::Axial);
            bb->setAxis(dvec3(0, 0, 1));
            bb->addChild(make<Geometry>(kinds[kind], treeMat));
            t->addChild(bb);
            outside->addChild(t);
            ++f.trees;
        };
        for (int k = 0; k < prm.trees; ++k) {
            for (int tries = 0; tries < 100; ++tries) {
                const double a = rng.uniform(0, 2 * M_PI), r = rng.uniform(200.0, std::min(half - 10.0, 360.0));
                const double x = r * std::cos(a), y = 10.0 + r * std::sin(a);
                if (std::abs(x - streamX(y)) < 12.0 || (std::abs(y + 20.0) < 8.0 && x > 150.0)) continue;
                plant(x, y, int(rng.uniform() < 0.5));
                break;
            }
        }
        for (double x = -150.0; x <= 20.0; x += 10.0) plant(x, 114.0, 0);
    }

    // --- Cars: one model (body, cabin, wheels) placed by Instance in the car park.
    {
        MeshBuilder body, wheels;
        body.box(dvec3(-2.1, -0.9, 0.3), dvec3(2.1, 0.9, 1.0), rgb(180, 40, 35));
        body.box(dvec3(-1.2, -0.8, 1.0), dvec3(0.9, 0.8, 1.5), rgb(150, 170, 190));
        for (double x : {-1.4, 1.4})
            for (double y : {-0.95, 0.75})
                wheels.frustum(dvec3(x, y, 0.33), dvec3(x, y + 0.2, 0.33), 0.33, 0.33, 10, rgb(30, 30, 30));
        auto car = make<Group>();
        car->setName("car");
        car->addChild(make<Geometry>(body.build(), glossy(0.6f, 64.0f)));
        car->addChild(make<Geometry>(wheels.build(), white));
        std::vector<int> slots;
        for (int s = 0; s < 64; ++s) slots.push_back(s);
        for (int k = 0; k < prm.cars; ++k) {  // a deterministic shuffle picks the occupied slots
            const int pick = k + int(rng.uniform() * (slots.size() - size_t(k)));
            std::swap(slots[size_t(k)], slots[size_t(std::min<int>(pick, int(slots.size()) - 1))]);
            const int s = slots[size_t(k)], row = s / 16, col = s % 16;
            const dmat4 m = glm::translate(dmat4(1.0), dvec3(101.5 + 3.0 * col, 24.5 + 16.0 * row, 0.05)) *
                            glm::rotate(dmat4(1.0), M_PI / 2, dvec3(0, 0, 1));
            outside->addChild(make<Instance>(car, m));
            ++f.cars;
        }
    }

    // --- Workshop interiors: 17 instances of one machine group, conveyors, pillars, inner walls.
    f.machineMesh = machineMesh(prm.seed ^ 0x5eedu, 2886);
    f.machine = makeLod(f.machineMesh, glossy(0.5f, 40.0f), {0.08f}, prm.pixelError);
    f.machine->setTransition(float(prm.fadeFraction * f.machine->range(1).min));
    f.machine->setName("machine group");
    {
        MeshBuilder pil, conv;
        pil.box(dvec3(-0.25, -0.25, 0.0), dvec3(0.25, 0.25, 9.5), rgb(160, 160, 155));
        conv.box(dvec3(-24.0, -0.4, 0.8), dvec3(24.0, 0.4, 0.9), rgb(60, 60, 60));  // belt
        for (double x = -23.5; x <= 23.5; x += 4.7) {
            conv.box(dvec3(x - 0.05, -0.4, 0.0), dvec3(x + 0.05, -0.3, 0.8), rgb(90, 90, 90));
            conv.box(dvec3(x - 0.05, 0.3, 0.0), dvec3(x + 0.05, 0.4, 0.8), rgb(90, 90, 90));
        }
        for (double x : {-24.0, 24.0})
            conv.frustum(dvec3(x, -0.45, 0.85), dvec3(x, 0.45, 0.85), 0.12, 0.12, 12, rgb(180, 185, 190));
        const ref_ptr<Mesh> pillar = pil.build(), conveyor = conv.build();
        for (int w = 0; w < 4; ++w) {
            const BuildingSpec& s = specs[size_t(w)];
            FactoryWorkshop ws;
            ws.building = w;
            ws.interior = make<Switch>();
            ws.interior->setName("workshop interior");
            ws.interiorGroup = make<Group>();
            auto place = make<Transform>();
            place->setTranslation(s.centre);
            // Floor, inner wall faces (inwards, 0.35 m inside the outer walls) and the ceiling.
            MeshBuilder shell;
            const double hw = s.w / 2 - 0.35, hd = s.d / 2 - 0.35, hc = s.h - 0.5;
            const vec2 t[4] = {kWhiteUv, kWhiteUv, kWhiteUv, kWhiteUv};
            const dvec3 floorQ[4] = {dvec3(-hw, -hd, 0.02), dvec3(hw, -hd, 0.02), dvec3(hw, hd, 0.02),
                                     dvec3(-hw, hd, 0.02)};
            shell.quad(floorQ, dvec3(0, 0, 1), t, rgb(150, 150, 145));
            const dvec3 ceilQ[4] = {dvec3(-hw, -hd, hc), dvec3(hw, -hd, hc), dvec3(hw, hd, hc), dvec3(-hw, hd, hc)};
            shell.quad(ceilQ, dvec3(0, 0, -1), t, rgb(200, 200, 195));
            const dvec3 corners[4] = {dvec3(-hw, -hd, 0), dvec3(hw, -hd, 0), dvec3(hw, hd, 0), dvec3(-hw, hd, 0)};
            for (int k = 0; k < 4; ++k) {
                const dvec3 a = corners[k], b = corners[(k + 1) % 4];
                const dvec3 q[4] = {a, b, b + dvec3(0, 0, hc), a + dvec3(0, 0, hc)};
                shell.quad(q, -glm::normalize(dvec3((a + b).x, (a + b).y, 0.0)), t, rgb(215, 212, 200));
            }
            ws.interiorGroup->addChild(make<Geometry>(shell.build(), white));
            for (double x = -hw + 5.0; x < hw - 1.0; x += 10.0)
                for (double y : {-hd + 2.0, hd - 2.0}) {
                    auto tp = make<Transform>();
                    tp->setTranslation(dvec3(x, y, 0.0));
                    tp->addChild(make<Geometry>(pillar, white));
                    ws.interiorGroup->addChild(tp);
                }
            for (double y : {-4.5, 4.5}) {
                auto tc = make<Transform>();
                tc->setTranslation(dvec3(0.0, y, 0.0));
                tc->addChild(make<Geometry>(conveyor, white));
                ws.interiorGroup->addChild(tc);
            }
            // Three rows along the hall; the middle row turned round so that every line faces a conveyor.
            const int n = prm.machinesPerWorkshop, perRow = (n + 2) / 3;
            for (int k = 0; k < n; ++k) {
                const int row = k / perRow, col = k % perRow;
                const double x = -hw + 4.5 + col * ((2.0 * hw - 9.0) / std::max(1, perRow - 1));
                const double y = (row - 1) * 9.0;
                dmat4 m = glm::translate(dmat4(1.0), dvec3(x, y, 0.0));
                if (row == 1) m = m * glm::rotate(dmat4(1.0), M_PI, dvec3(0, 0, 1));
                ws.interiorGroup->addChild(make<Instance>(f.machine, m));
                ++f.machines;
            }
            place->addChild(ws.interiorGroup);
            ws.interior->addChild(place, false);
            interiors->addChild(ws.interior);
            f.workshops.push_back(ws);
        }
    }

    TriangleCount tc;
    tc.walk(*f.root);
    f.drawnTriangles = tc.drawn;
    f.storedTriangles = tc.stored;
    return f;
}

void shareTerrainColors(Factory& f) {
    for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
        Node& tile = *f.terrain->child(t);
        const Mesh& fine = *static_cast<Geometry&>(*tile.child(0)).mesh();
        const std::vector<vec3>& fp = fine.positions();
        const std::vector<vec4>& fc = fine.colors();
        const int side = int(std::lround(std::sqrt(double(fp.size())))), per = side - 1;
        const std::vector<int> cells = terrainLevelCells(per);
        if (per < 1 || fc.size() != fp.size() || cells.size() != tile.numChildren())
            throw std::invalid_argument("scenes::shareTerrainColors(): terrain tile " + std::to_string(t) +
                                        " is not as buildFactory() made it");
        const double x0 = fp[0].x, y0 = fp[0].y, step = (double(fp[size_t(per)].x) - x0) / per;
        LOD& lod = static_cast<LOD&>(tile);
        for (size_t level = 1; level < tile.numChildren(); ++level) {
            Mesh& m = *static_cast<Geometry&>(*tile.child(level)).mesh();
            // Half the level's spacing, in cells: the neighbourhood an inner vertex stands for.
            const int r = int(std::lround(0.5 * per / cells[level]));
            std::vector<vec4> col(m.positions().size());
            // The level's light as an error in metres, for the LOD budget's valuation: a shadow's edge that
            // a coarse vertex blurs over its neighbourhood counts as an edge that far out of place, scaled by
            // how much the colour changes there (the worst channel's difference from the mean, 0-1). The
            // geometry can be exact (a flat yard) while the shadow of the building beside it is lost.
            float worst = 0.0f;
            for (size_t v = 0; v < col.size(); ++v) {
                const int li = int(std::lround((m.positions()[v].x - x0) / step)),
                          lj = int(std::lround((m.positions()[v].y - y0) / step));
                if (li == 0 || lj == 0 || li == per || lj == per) {  // the shared border: exactly the finest
                    col[v] = fc[size_t(lj * side + li)];
                    continue;
                }
                vec4 sum(0.0f);
                int n = 0;
                for (int j = std::max(0, lj - r); j <= std::min(per, lj + r); ++j)
                    for (int i = std::max(0, li - r); i <= std::min(per, li + r); ++i, ++n)
                        sum += fc[size_t(j * side + i)];
                col[v] = sum / float(n);
                for (int j = std::max(0, lj - r); j <= std::min(per, lj + r); ++j)
                    for (int i = std::max(0, li - r); i <= std::min(per, li + r); ++i) {
                        const vec4 d = glm::abs(fc[size_t(j * side + i)] - col[v]);
                        worst = std::max({worst, d.r, d.g, d.b});
                    }
            }
            const float light = worst * float(step * per / cells[level]);
            lod.setError(level, std::max({lod.error(level), lod.error(level - 1), light}));
            std::vector<uint32_t> idx(m.indexCount());
            for (size_t i = 0; i < idx.size(); ++i) idx[i] = m.index(i);
            m.set(m.positions(), m.normals(), std::move(idx), m.uvs(), std::move(col));
        }
    }
}

void shareBuildingColors(Factory& f) {
    for (size_t bi = 0; bi < f.buildings.size(); ++bi) {
        const FactoryBuilding& b = f.buildings[bi];
        const std::vector<vec4>& fc = static_cast<const Geometry&>(*b.lod->child(0)).mesh()->colors();
        if (b.coarseColors.size() + 1 != b.lod->numChildren())
            throw std::invalid_argument("scenes::shareBuildingColors(): building " + std::to_string(bi) + " has " +
                                        std::to_string(b.coarseColors.size()) + " colour shares for " +
                                        std::to_string(b.lod->numChildren() - 1) + " coarse levels");
        for (size_t level = 1; level < b.lod->numChildren(); ++level)
            applyColorShare(b.coarseColors[level - 1], fc, *static_cast<const Geometry&>(*b.lod->child(level)).mesh(),
                            "scenes::shareBuildingColors()");
    }
}

int factoryWorkshopAt(const Factory& f, const dvec3& eye) {
    for (size_t k = 0; k < f.workshops.size(); ++k)
        if (f.buildings[size_t(f.workshops[k].building)].box.contains(eye)) return int(k);
    return -1;
}

void setFactoryEye(Factory& f, int workshop) {
    if (workshop >= int(f.workshops.size()))
        throw std::out_of_range("scenes::setFactoryEye(): workshop " + std::to_string(workshop) + " of " +
                                std::to_string(f.workshops.size()));
    f.outside->setAll(workshop < 0);
    for (size_t k = 0; k < f.workshops.size(); ++k) f.workshops[k].interior->setAll(int(k) == workshop);
}

Camera factoryOrbitCamera(int frame, int width, int height) {
    const double a = 2.0 * M_PI * frame / kFactoryOrbitFrames;
    const dvec3 target(-20.0, 20.0, 0.0);
    const dvec3 eye = target + dvec3(300.0 * std::cos(a), 300.0 * std::sin(a), 90.0);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, double(width) / height, 1.0, 3000.0);
    cam.setLookAt(eye, target, dvec3(0, 0, 1));
    return cam;
}

Camera factoryWorkshopCamera(const Factory& f, int workshop, int width, int height) {
    const Box& b = f.buildings.at(size_t(f.workshops.at(size_t(workshop)).building)).box;
    const dvec3 eye(b.min.x + 2.0, b.center().y - 2.0, 1.7);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, double(width) / height, 0.1, 500.0);
    cam.setLookAt(eye, eye + dvec3(1.0, 0.05, -0.08), dvec3(0, 0, 1));
    return cam;
}

}  // namespace scenes
