// OsgCity: the canonical `city` scene (shared/bench city.md) and its camera paths, built with OpenSceneGraph 3.6
// for the peer programs (sgbench_osg: the cull, sgframe_osg: whole frames in a window). One shared Geometry per
// distinct building height and level of detail, and one car, exactly as sgkit's own city shares its meshes.
#pragma once
#include <osg/ConvexPlanarOccluder>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/LOD>
#include <osg/MatrixTransform>
#include <osg/OccluderNode>
#include <osg/PrimitiveSet>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace osgcity {

// ---------------------------------------------------------------------------
// Scene definition constants (units metres, +Z up).

constexpr double kCellSize = 20.0;
constexpr double kFootprint = 12.0;  // building footprint, centred in the cell
constexpr double kCarSize[3] = {4.0, 2.0, 1.5};
constexpr double kCarOffset = 1.0;  // car minimum corner at (20i+1, 20j+1, 0)
constexpr unsigned kMinHeight = 10;
constexpr unsigned kHeightCount = 51;  // heights 10..60
constexpr int kTileCells = 8;          // tiles group 8x8 cells
constexpr float kDetailFar = 250.0f;   // detailed LOD: [0, 250)
constexpr float kCoarseFar = 2500.0f;  // coarse LOD:   [250, 2500)
constexpr int kDetailSubdiv = 10;      // 10x10 quads per face -> 1200 triangles

// Camera paths.
constexpr int kFrames = 120;        // orbit
constexpr int kStreetFrames = 240;  // street
constexpr int kViewportW = 1280;
constexpr int kViewportH = 720;
constexpr double kFovY = 60.0;
constexpr double kAspect = 16.0 / 9.0;
constexpr double kNear = 1.0;        // orbit
constexpr double kStreetNear = 0.5;  // street
constexpr double kFar = 3000.0;

inline unsigned buildingHeight(uint32_t i, uint32_t j) {
    // Unsigned 32-bit arithmetic, exactly as in the scene definition.
    return kMinHeight + ((i * 73856093u) ^ (j * 19349663u)) % kHeightCount;
}

// ---------------------------------------------------------------------------
// Geometry: an axis-aligned box [lo, hi] whose faces are each split into
// subdiv x subdiv quads, as indexed triangles with outward per-vertex normals
// (counter-clockwise winding seen from outside).

inline osg::ref_ptr<osg::Geometry> makeBox(const osg::Vec3& lo, const osg::Vec3& hi, int subdiv) {
    const osg::Vec3 d = hi - lo;
    struct Face {
        osg::Vec3 origin, u, v, normal;
    };
    // u x v == normal for each face, which makes the quads wind outward.
    const Face faces[6] = {
        {{hi.x(), lo.y(), lo.z()}, {0, d.y(), 0}, {0, 0, d.z()}, {1, 0, 0}},    // +X
        {{lo.x(), hi.y(), lo.z()}, {0, -d.y(), 0}, {0, 0, d.z()}, {-1, 0, 0}},  // -X
        {{hi.x(), hi.y(), lo.z()}, {-d.x(), 0, 0}, {0, 0, d.z()}, {0, 1, 0}},   // +Y
        {{lo.x(), lo.y(), lo.z()}, {d.x(), 0, 0}, {0, 0, d.z()}, {0, -1, 0}},   // -Y
        {{lo.x(), lo.y(), hi.z()}, {d.x(), 0, 0}, {0, d.y(), 0}, {0, 0, 1}},    // +Z
        {{lo.x(), hi.y(), lo.z()}, {d.x(), 0, 0}, {0, -d.y(), 0}, {0, 0, -1}},  // -Z
    };

    const int side = subdiv + 1;
    osg::ref_ptr<osg::Vec3Array> vertices = new osg::Vec3Array;
    osg::ref_ptr<osg::Vec3Array> normals = new osg::Vec3Array;
    osg::ref_ptr<osg::DrawElementsUShort> triangles = new osg::DrawElementsUShort(GL_TRIANGLES);
    vertices->reserve(6 * side * side);
    normals->reserve(6 * side * side);
    triangles->reserve(6 * subdiv * subdiv * 6);

    for (const Face& f : faces) {
        const unsigned base = vertices->size();
        for (int b = 0; b < side; ++b) {
            for (int a = 0; a < side; ++a) {
                vertices->push_back(f.origin + f.u * (float(a) / subdiv) + f.v * (float(b) / subdiv));
                normals->push_back(f.normal);
            }
        }
        for (int b = 0; b < subdiv; ++b) {
            for (int a = 0; a < subdiv; ++a) {
                const unsigned short v00 = base + b * side + a;
                const unsigned short v10 = v00 + 1;
                const unsigned short v11 = v10 + side;
                const unsigned short v01 = v00 + side;
                triangles->push_back(v00);
                triangles->push_back(v10);
                triangles->push_back(v11);
                triangles->push_back(v00);
                triangles->push_back(v11);
                triangles->push_back(v01);
            }
        }
    }

    osg::ref_ptr<osg::Geometry> geom = new osg::Geometry;
    geom->setVertexArray(vertices.get());
    geom->setNormalArray(normals.get(), osg::Array::BIND_PER_VERTEX);
    geom->addPrimitiveSet(triangles.get());
    return geom;
}

inline unsigned triangleCount(const osg::Geometry& geom) {
    unsigned n = 0;
    for (unsigned p = 0; p < geom.getNumPrimitiveSets(); ++p) n += geom.getPrimitiveSet(p)->getNumIndices() / 3;
    return n;
}

// ---------------------------------------------------------------------------
// Occluder polygons for a building of height h, in the building's frame
// (footprint centred on the origin, z from 0 to h).

enum class OccluderKind { None, Box, Sides, Diagonals };

inline const char* occluderKindName(OccluderKind k) {
    switch (k) {
        case OccluderKind::None: return "none";
        case OccluderKind::Box: return "box";
        case OccluderKind::Sides: return "sides";
        case OccluderKind::Diagonals: return "diagonals";
    }
    return "?";
}

inline std::vector<std::array<osg::Vec3, 4>> occluderPolygons(OccluderKind kind, float h) {
    const float s = float(kFootprint / 2);
    std::vector<std::array<osg::Vec3, 4>> polys;
    if (kind == OccluderKind::Box || kind == OccluderKind::Sides) {
        polys.push_back({{{s, -s, 0}, {s, s, 0}, {s, s, h}, {s, -s, h}}});      // +X
        polys.push_back({{{-s, s, 0}, {-s, -s, 0}, {-s, -s, h}, {-s, s, h}}});  // -X
        polys.push_back({{{s, s, 0}, {-s, s, 0}, {-s, s, h}, {s, s, h}}});      // +Y
        polys.push_back({{{-s, -s, 0}, {s, -s, 0}, {s, -s, h}, {-s, -s, h}}});  // -Y
    }
    if (kind == OccluderKind::Box) polys.push_back({{{-s, -s, h}, {s, -s, h}, {s, s, h}, {-s, s, h}}});  // roof
    if (kind == OccluderKind::Diagonals) {
        polys.push_back({{{-s, -s, 0}, {s, s, 0}, {s, s, h}, {-s, -s, h}}});
        polys.push_back({{{s, -s, 0}, {-s, s, 0}, {-s, s, h}, {s, -s, h}}});
    }
    return polys;
}

// ---------------------------------------------------------------------------
// Scene construction.

// Shared resources: one detailed and one coarse box per distinct height, one
// car, and the occluder polygons per height.
struct Meshes {
    std::vector<osg::ref_ptr<osg::Geometry>> detailed, coarse;
    osg::ref_ptr<osg::Geometry> car;
    std::vector<std::vector<osg::ref_ptr<osg::ConvexPlanarOccluder>>> occluders;  // [height index][polygon]
    // Triangles per shared Geometry, used only to verify cull output.
    std::unordered_map<const osg::Drawable*, unsigned> triangles;
};

inline Meshes buildMeshes(OccluderKind occluders) {
    Meshes m;
    const float half = float(kFootprint / 2);
    // Buildings are centred on their transform in x,y, z from 0 to h.
    m.detailed.resize(kHeightCount);
    m.coarse.resize(kHeightCount);
    m.occluders.resize(kHeightCount);
    for (unsigned k = 0; k < kHeightCount; ++k) {
        const float h = float(kMinHeight + k);
        m.detailed[k] = makeBox({-half, -half, 0}, {half, half, h}, kDetailSubdiv);
        m.coarse[k] = makeBox({-half, -half, 0}, {half, half, h}, 1);
        m.triangles[m.detailed[k].get()] = triangleCount(*m.detailed[k]);
        m.triangles[m.coarse[k].get()] = triangleCount(*m.coarse[k]);
        for (const auto& poly : occluderPolygons(occluders, h)) {
            osg::ref_ptr<osg::ConvexPlanarOccluder> cpo = new osg::ConvexPlanarOccluder;
            for (const osg::Vec3& v : poly) cpo->getOccluder().add(v);
            m.occluders[k].push_back(cpo);
        }
    }
    m.car = makeBox({0, 0, 0}, {float(kCarSize[0]), float(kCarSize[1]), float(kCarSize[2])}, 1);
    m.triangles[m.car.get()] = triangleCount(*m.car);
    return m;
}

struct Scene {
    osg::ref_ptr<osg::Group> root;
    uint64_t nodes = 0;
    const Meshes* meshes = nullptr;
};

// withOccluders: each building's MatrixTransform also holds one OccluderNode
// per polygon in meshes.occluders, beside the LOD; with occluderRange > 0 they
// are the children of a second LOD (same centre) active in [0, occluderRange).
inline Scene buildCity(int n, const Meshes& meshes, bool withOccluders, float occluderRange = 0.0f) {
    Scene scene;
    scene.meshes = &meshes;
    scene.root = new osg::Group;
    scene.nodes = 1;
    const int tiles = (n + kTileCells - 1) / kTileCells;
    for (int ti = 0; ti < tiles; ++ti) {
        for (int tj = 0; tj < tiles; ++tj) {
            osg::ref_ptr<osg::Group> tile = new osg::Group;
            scene.root->addChild(tile.get());
            ++scene.nodes;
            const int iEnd = std::min(n, (ti + 1) * kTileCells);
            const int jEnd = std::min(n, (tj + 1) * kTileCells);
            for (int i = ti * kTileCells; i < iEnd; ++i) {
                for (int j = tj * kTileCells; j < jEnd; ++j) {
                    const unsigned h = buildingHeight(uint32_t(i), uint32_t(j));
                    const unsigned k = h - kMinHeight;
                    const double x0 = kCellSize * i, y0 = kCellSize * j;

                    osg::ref_ptr<osg::Group> cell = new osg::Group;

                    osg::ref_ptr<osg::MatrixTransform> buildingXf =
                        new osg::MatrixTransform(osg::Matrixd::translate(x0 + kCellSize / 2, y0 + kCellSize / 2, 0.0));
                    osg::ref_ptr<osg::LOD> lod = new osg::LOD;
                    // The range is measured from the eye to a user-defined centre
                    // (the middle of the building), not to the bounding-sphere
                    // centre. The LOD's radius is left unset so its bound is the
                    // union of its children's bounds, which is the same box sphere.
                    lod->setCenterMode(osg::LOD::USER_DEFINED_CENTER);
                    lod->setCenter(osg::Vec3(0.0f, 0.0f, float(h) / 2.0f));
                    lod->setRangeMode(osg::LOD::DISTANCE_FROM_EYE_POINT);
                    osg::ref_ptr<osg::Geode> detailGeode = new osg::Geode;
                    detailGeode->addDrawable(meshes.detailed[k].get());
                    osg::ref_ptr<osg::Geode> coarseGeode = new osg::Geode;
                    coarseGeode->addDrawable(meshes.coarse[k].get());
                    // OSG's LOD selects child c when min <= distance < max.
                    lod->addChild(detailGeode.get(), 0.0f, kDetailFar);
                    lod->addChild(coarseGeode.get(), kDetailFar, kCoarseFar);
                    buildingXf->addChild(lod.get());
                    if (withOccluders) {
                        osg::ref_ptr<osg::LOD> occLod;
                        if (occluderRange > 0.0f) {
                            occLod = new osg::LOD;
                            occLod->setCenterMode(osg::LOD::USER_DEFINED_CENTER);
                            occLod->setCenter(osg::Vec3(0.0f, 0.0f, float(h) / 2.0f));
                            occLod->setRangeMode(osg::LOD::DISTANCE_FROM_EYE_POINT);
                            buildingXf->addChild(occLod.get());
                            ++scene.nodes;
                        }
                        for (const auto& cpo : meshes.occluders[k]) {
                            osg::ref_ptr<osg::OccluderNode> occ = new osg::OccluderNode;
                            occ->setOccluder(cpo.get());
                            if (occLod)
                                occLod->addChild(occ.get(), 0.0f, occluderRange);
                            else
                                buildingXf->addChild(occ.get());
                            ++scene.nodes;
                        }
                    }

                    osg::ref_ptr<osg::MatrixTransform> carXf =
                        new osg::MatrixTransform(osg::Matrixd::translate(x0 + kCarOffset, y0 + kCarOffset, 0.0));
                    osg::ref_ptr<osg::Geode> carGeode = new osg::Geode;
                    carGeode->addDrawable(meshes.car.get());
                    carXf->addChild(carGeode.get());

                    cell->addChild(buildingXf.get());
                    cell->addChild(carXf.get());
                    tile->addChild(cell.get());
                    scene.nodes += 7;  // cell, 2 transforms, LOD, 3 geodes
                }
            }
        }
    }

    // Compute every bounding sphere now (OSG computes them lazily on first
    // use), so the cull passes never pay for it.
    scene.root->getBound();
    return scene;
}

// ---------------------------------------------------------------------------
// Camera paths.

inline osg::Matrixd orbitView(int n, int frame) {
    const double a = 2.0 * M_PI * frame / kFrames;
    const osg::Vec3d c(10.0 * n, 10.0 * n, 0.0);
    const osg::Vec3d eye = c + osg::Vec3d(5.0 * n * std::cos(a), 5.0 * n * std::sin(a), 40.0);
    osg::Vec3d d(-std::sin(a), std::cos(a), -0.15);
    d.normalize();
    return osg::Matrixd::lookAt(eye, eye + d, osg::Vec3d(0.0, 0.0, 1.0));
}

// The street between two cell columns, walked end to end, the view swaying left and right.
inline osg::Matrixd streetView(int n, int frame) {
    const osg::Vec3d eye(20.0 * std::floor(n / 2.0), 20.0 * n * frame / double(kStreetFrames - 1), 1.7);
    const double t = 0.5 * std::sin(2.0 * M_PI * frame / 60.0);
    const osg::Vec3d d(std::sin(t), std::cos(t), 0.0);
    return osg::Matrixd::lookAt(eye, eye + d, osg::Vec3d(0.0, 0.0, 1.0));
}

}  // namespace osgcity
