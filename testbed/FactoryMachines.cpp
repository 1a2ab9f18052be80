// The factory's workshop interiors: the machine group (one levelled model placed by Instance), conveyors,
// pillars, the inner shell, each workshop behind its Switch.
#include "testbed/FactoryBuild.h"

#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/build/LodGenerator.h"

#include <algorithm>
#include <cmath>

namespace scenes::factory {

namespace {

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

}  // namespace

// Workshop interiors: 17 instances of one machine group, conveyors, pillars, inner walls.
void addWorkshops(FactorySite& site) {
    const FactoryParams& prm = site.prm;
    Factory& f = site.f;
    const ref_ptr<Group>& interiors = site.interiors;
    const ref_ptr<Material>& white = site.white;
    f.machineMesh = machineMesh(prm.seed ^ 0x5eedu, 2886);
    f.machine = makeLod(f.machineMesh, glossyMaterial(0.5f, 40.0f), {0.08f}, prm.pixelError);
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
            const BuildingSpec& s = buildingSpecs()[size_t(w)];
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
}

}  // namespace scenes::factory
