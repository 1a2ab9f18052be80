// The factory's buildings: their detailed models (walls with window details, roofs, doors, vents), levelled with
// the coarse levels reshaded from the detailed surface, their occluders, and the coarse levels' colours after baked
// light.
#include "testbed/FactoryBuild.h"

#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/build/LodGenerator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace scenes {

namespace factory {

namespace {

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

}  // namespace

const std::vector<BuildingSpec>& buildingSpecs() {
    static const std::vector<BuildingSpec> specs = {
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
    return specs;
}

// Buildings: each a levelled model with its roof beside it, placed by a Transform, and an occluder.
void addBuildings(FactorySite& site) {
    const FactoryParams& prm = site.prm;
    Factory& f = site.f;
    const ref_ptr<Group>& outside = site.outside;
    const ref_ptr<Group>& occluders = site.occluders;
    const std::vector<BuildingSpec>& specs = buildingSpecs();
    const auto wallMat = make<Material>(vec4(1.0f), factoryWindowTexture());
    const auto brickMat = make<Material>(vec4(1.0f), factoryBrickTexture(prm.seed));
    const auto roofMat = texturedMaterial(factoryRoofTexture(prm.seed), 4.0f, 0.45f, 48.0f);
    // Walls are faceted: coarse levels shaded from the detailed surface, the walls' white corner where none is near.
    LevelShading reshaded;
    reshaded.reshade = true;
    reshaded.params.fallbackUv = kWhiteUv;
    for (const BuildingSpec& s : specs) {
        FactoryBuilding b;
        b.kind = s.kind;
        b.place = make<Transform>();
        b.place->setTranslation(s.centre);
        const std::vector<LodLevel> levels =
            generateLevels(buildingMesh(s), {0.25f, 0.06f}, std::numeric_limits<float>::infinity(), reshaded);
        b.lod = makeLod(levels, s.brick ? brickMat : wallMat, prm.pixelError);
        for (size_t i = 1; i < levels.size(); ++i) b.coarseColors.push_back(levels[i].colors);
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
}

}  // namespace factory

using namespace sg;

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

}  // namespace scenes
