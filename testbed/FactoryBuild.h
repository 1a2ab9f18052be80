// The parts of buildFactory() (testbed/Factory.cpp): the state its sections share and one function per section,
// called in order (the random stream and the order of made meshes and materials are part of the scene).
#pragma once
#include "testbed/Factory.h"

#include "testbed/FactoryTextures.h"
#include "testbed/Rng.h"

#include "sg/core/Material.h"
#include "sg/core/Math.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace scenes::factory {

using namespace sg;

// The factory's stream: 32-bit mt19937, its top 24 bits per uniform (the site's layout depends on it).
using Rng = BasicRng<std::mt19937>;

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

inline vec4 rgb(int r, int g, int b) { return vec4(r / 255.0f, g / 255.0f, b / 255.0f, 1.0f); }

// One material per texture, shared by every mesh that shows it: the draw batches stay per mesh.
ref_ptr<Material> texturedMaterial(ref_ptr<Texture> tex, float anisotropy, float specular = 0.0f,
                                   float shininess = 32.0f);
// Painted and metal surfaces catch the sun; the rest stays matt.
ref_ptr<Material> glossyMaterial(float specular, float shininess);

struct BuildingSpec {
    const char* kind;
    dvec3 centre;        // ground centre
    double w, d, h;      // extent along x, y, and wall height
    double storey, bay;  // window grid
    vec4 wall, roof;
    bool sawtooth;  // workshops: north-light roof prisms
    bool brick;     // brick walls (their colour in the texture) rather than rendered ones tinted by `wall`
};

// The 11 buildings: workshops first (4), then auxiliary (5), technology, office.
const std::vector<BuildingSpec>& buildingSpecs();

// What the sections share while the factory is built.
struct FactorySite {
    const FactoryParams& prm;
    Factory& f;
    ref_ptr<Group> outside;    // under f.outside: everything a closed workshop hides
    ref_ptr<Group> occluders;  // the buildings' occluders (not switched)
    ref_ptr<Group> interiors;  // the workshops' interior Switches
    ref_ptr<Material> white;
    Rng rng;
    double ph[4] = {};  // the hills' phases: the first draws of rng
    double half = 0.0;  // half the site's side

    // The stream's centre line.
    static double streamX(double y) { return 175.0 + 15.0 * std::sin(y / 50.0); }
    // Rolling hills around a flat yard (radius ~210 m), before the stream's channel is cut.
    double hills(double x, double y) const {
        const double r = std::hypot(x, y - 10.0);
        const double t = std::clamp((r - 210.0) / 130.0, 0.0, 1.0);
        const double w = t * t * (3.0 - 2.0 * t);
        const double hgt = 16.0 + 9.0 * std::sin(x / 70.0 + ph[0]) * std::cos(y / 90.0 + ph[1]) +
                           6.0 * std::sin((x + y) / 45.0 + ph[2]) + 4.0 * std::cos(x / 33.0 - y / 51.0 + ph[3]);
        return w * hgt;
    }
};

// The sections, in the order buildFactory() calls them.
void addTerrain(FactorySite& site);    // FactoryTerrain.cpp
void addRoads(FactorySite& site);      // FactoryGrounds.cpp
void addStream(FactorySite& site);     // FactoryGrounds.cpp
void addChimney(FactorySite& site);    // FactoryGrounds.cpp
void addBuildings(FactorySite& site);  // FactoryBuildings.cpp
void addTrees(FactorySite& site);      // FactoryGrounds.cpp
void addCars(FactorySite& site);       // FactoryGrounds.cpp
void addWorkshops(FactorySite& site);  // FactoryMachines.cpp
void addFeatures(FactorySite& site);   // FactoryFeatures.cpp: after the buildings and workshops

}  // namespace scenes::factory
