// The factory's grounds: roads and the car park, the stream and its bridge, the chimney, the trees and the cars.
#include "testbed/FactoryBuild.h"

#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/Transform.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace scenes::factory {

// Roads and the car park: flat quads just above the yard, asphalt in world metres, painted lines.
void addRoads(FactorySite& site) {
    const FactoryParams& prm = site.prm;
    const ref_ptr<Group>& outside = site.outside;
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
    const double bridgeX = site.streamX(-20.0);
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
    outside->addChild(make<Geometry>(mb.build(), texturedMaterial(factoryAsphaltTexture(prm.seed), 8.0f)));
}

// The stream (a water strip in its channel) and the bridge carrying the main road over it.
void addStream(FactorySite& site) {
    const ref_ptr<Group>& outside = site.outside;
    const ref_ptr<Material>& white = site.white;
    const double half = site.half;
    MeshBuilder mb;
    const vec2 t[4] = {kWhiteUv, kWhiteUv, kWhiteUv, kWhiteUv};
    for (double y = -half; y < half - 1e-9; y += 8.0) {
        const double y1 = std::min(y + 8.0, half);
        const double z0 = site.hills(site.streamX(y), y) - 0.9, z1 = site.hills(site.streamX(y1), y1) - 0.9;
        const dvec3 q[4] = {dvec3(site.streamX(y) - 5.5, y, z0), dvec3(site.streamX(y) + 5.5, y, z0),
                            dvec3(site.streamX(y1) + 5.5, y1, z1), dvec3(site.streamX(y1) - 5.5, y1, z1)};
        mb.quad(q, dvec3(0, 0, 1), t, rgb(60, 110, 160));
    }
    outside->addChild(make<Geometry>(mb.build(), white));
    MeshBuilder br;
    const double bx = site.streamX(-20.0);
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

// The boiler house chimney.
void addChimney(FactorySite& site) {
    const ref_ptr<Group>& outside = site.outside;
    const ref_ptr<Material>& white = site.white;
    MeshBuilder mb;
    mb.frustum(dvec3(70, -45, 0), dvec3(70, -45, 45), 3.0, 1.8, 32, rgb(150, 80, 60));
    for (double z : {15.0, 30.0, 43.0})
        mb.frustum(dvec3(70, -45, z), dvec3(70, -45, z + 0.8), 2.2, 2.2, 32, rgb(110, 110, 110));
    outside->addChild(make<Geometry>(mb.build(), white));
}

// Trees: axial billboards (one shared crown-and-trunk polygon per kind) around the yard and along
// the north road.
void addTrees(FactorySite& site) {
    const FactoryParams& prm = site.prm;
    Factory& f = site.f;
    const ref_ptr<Group>& outside = site.outside;
    Rng& rng = site.rng;
    const double half = site.half;
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
            if (std::abs(x - site.streamX(y)) < 12.0 || (std::abs(y + 20.0) < 8.0 && x > 150.0)) continue;
            plant(x, y, int(rng.uniform() < 0.5));
            break;
        }
    }
    for (double x = -150.0; x <= 20.0; x += 10.0) plant(x, 114.0, 0);
}

// Cars: one model (body, cabin, wheels) placed by Instance in the car park.
void addCars(FactorySite& site) {
    const FactoryParams& prm = site.prm;
    Factory& f = site.f;
    const ref_ptr<Group>& outside = site.outside;
    const ref_ptr<Material>& white = site.white;
    Rng& rng = site.rng;
    MeshBuilder body, wheels;
    body.box(dvec3(-2.1, -0.9, 0.3), dvec3(2.1, 0.9, 1.0), rgb(180, 40, 35));
    body.box(dvec3(-1.2, -0.8, 1.0), dvec3(0.9, 0.8, 1.5), rgb(150, 170, 190));
    for (double x : {-1.4, 1.4})
        for (double y : {-0.95, 0.75})
            wheels.frustum(dvec3(x, y, 0.33), dvec3(x, y + 0.2, 0.33), 0.33, 0.33, 10, rgb(30, 30, 30));
    auto car = make<Group>();
    car->setName("car");
    car->addChild(make<Geometry>(body.build(), glossyMaterial(0.6f, 64.0f)));
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

}  // namespace scenes::factory
