// GeneratedOccluders: boxes inside closed meshes (checked against the solid with a winding number, ray parity, a
// triangle-box overlap test and rays from outside, all computed here in double precision), convex polygons on the
// faces of open ones, and the occluder nodes generateOccluders adds to a graph.
#include "sg/scene/GeneratedOccluders.h"

#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "scene/OccluderTestShapes.h"
#include "sg/scene/Scene.h"
#include "testbed/Rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace sg;
using namespace occtest;

namespace {

// Every box lies wholly inside the solid of `mesh`: no triangle meets it; at its corners, face and edge centres and
// random points the winding number is 1 or more, and the signed crossings along three random rays (ray parity, the
// sign kept) agree with it; and every ray from outside the mesh's bound into the box crosses the surface first.
void expectInsideSolid(const Mesh& mesh, const std::vector<Box>& boxes, scenes::Rng& rng, const std::string& what,
                       int points = 40, int rays = 60) {
    const std::vector<Tri> tris = trianglesOf(mesh);
    const Box bound = mesh.box();
    const double size = glm::length(bound.max - bound.min);
    for (size_t k = 0; k < boxes.size(); ++k) {
        const Box& b = boxes[k];
        SCOPED_TRACE(what + ": box " + std::to_string(k) + " " + str(b));
        ASSERT_FALSE(b.empty());
        ASSERT_TRUE(isFinite(b.min) && isFinite(b.max));
        EXPECT_GT(volume(b), 0.0);
        for (size_t t = 0; t < tris.size(); ++t)
            ASSERT_FALSE(triangleMeetsBox(tris[t], b)) << "triangle " << t << " meets the box";
        for (const dvec3& p : samplesOf(b, rng, points)) {
            const double w = windingNumber(tris, p);
            ASSERT_GT(w, 0.5) << "point (" << p.x << " " << p.y << " " << p.z << ") winding number " << w;
            ASSERT_NEAR(w, std::round(w), 1e-6) << "point off the surface but a winding number not whole";
            for (int r = 0; r < 3; ++r) {
                const dvec3 d = randomDirection(rng);
                ASSERT_EQ(signedCrossings(tris, p, d), int(std::round(w)))
                    << "point (" << p.x << " " << p.y << " " << p.z << "): crossings along (" << d.x << " " << d.y
                    << " " << d.z << ") disagree with the winding number";
            }
        }
        for (int r = 0; r < rays; ++r) {
            const dvec3 o = bound.center() + randomDirection(rng) * (size * 2.0 + 1.0);
            const dvec3 target(rng.uniform(b.min.x, b.max.x), rng.uniform(b.min.y, b.max.y),
                               rng.uniform(b.min.z, b.max.z));
            const dvec3 d = target - o;
            const double enter = entryInto(b, o, d), hit = firstHit(tris, o, d);
            ASSERT_LE(enter, 1.0);
            ASSERT_LE(hit, enter) << "ray " << r << " from (" << o.x << " " << o.y << " " << o.z
                                  << ") reaches the box before any surface";
        }
    }
}

// For shapes turned any way: a finer grid and a lower share, since an axis-aligned box fills little of a turned
// shape's bound.
OccluderGenSettings turned(OccluderGenSettings s = {}) {
    s.voxels = 64;
    s.minBoxShare = 0.001;
    return s;
}

// Count, order and size of the boxes of a closed mesh.
void expectBoxRules(const Mesh& mesh, const MeshOccluders& occ, const OccluderGenSettings& s) {
    EXPECT_TRUE(occ.closed);
    EXPECT_TRUE(occ.polygons.empty());
    EXPECT_LE(occ.boxes.size(), size_t(s.maxBoxes));
    const double boundVolume = volume(mesh.box());
    for (size_t k = 0; k < occ.boxes.size(); ++k) {
        EXPECT_GE(volume(occ.boxes[k]), s.minBoxShare * boundVolume * (1.0 - 1e-9)) << "box " << k << " too small";
        if (k > 0) {  // equal cell counts may differ in the last bits
            EXPECT_GE(volume(occ.boxes[k - 1]), volume(occ.boxes[k]) * (1.0 - 1e-9)) << "not largest first at " << k;
        }
    }
    if (!occ.boxes.empty()) {
        EXPECT_GT(occ.voxelsInside, 0u);
    }
}

// --- Polygons.

dvec3 newellNormal(const std::vector<dvec3>& poly) {  // length: twice the area
    dvec3 n(0.0);
    const dvec3 o = poly[0];
    for (size_t i = 1; i + 1 < poly.size(); ++i) n += glm::cross(poly[i] - o, poly[i + 1] - o);
    return n;
}
double area(const std::vector<dvec3>& poly) { return 0.5 * glm::length(newellNormal(poly)); }

// The rounding allowance of a mesh's float positions: relative to its size and to how far it is from the origin.
double toleranceOf(const Mesh& m) {
    const Box b = m.box();
    return 1e-5 * (glm::length(b.max - b.min) + std::max(glm::length(b.min), glm::length(b.max)));
}

// Planar and convex, turning counter-clockwise about its own normal (every corner turns the same way), by `tol`.
void expectConvexPlanar(const std::vector<dvec3>& poly, double tol) {
    ASSERT_GE(poly.size(), 3u);
    for (const dvec3& v : poly) ASSERT_TRUE(isFinite(v));
    const dvec3 n = newellNormal(poly);
    ASSERT_GT(glm::length(n), 0.0);
    const dvec3 un = glm::normalize(n);
    for (const dvec3& v : poly) EXPECT_NEAR(glm::dot(v - poly[0], un), 0.0, tol) << "not planar";
    for (size_t i = 0; i < poly.size(); ++i) {
        const dvec3 &a = poly[i], &b = poly[(i + 1) % poly.size()], &c = poly[(i + 2) % poly.size()];
        const double turn = glm::dot(glm::cross(b - a, c - b), un);
        EXPECT_GE(turn, -tol * (glm::length(b - a) + glm::length(c - b)))
            << "not convex at corner " << (i + 1) % poly.size();
    }
}

// Random points of a convex polygon: its corners, edge midpoints, centroid and points of its fan's triangles.
std::vector<dvec3> samplesOf(const std::vector<dvec3>& poly, scenes::Rng& rng, int random) {
    std::vector<dvec3> out(poly.begin(), poly.end());
    dvec3 c(0.0);
    for (size_t i = 0; i < poly.size(); ++i) {
        out.push_back((poly[i] + poly[(i + 1) % poly.size()]) * 0.5);
        c += poly[i];
    }
    out.push_back(c / double(poly.size()));
    for (int k = 0; k < random; ++k) {
        const size_t i = 1 + size_t(rng.below(int(poly.size()) - 2));
        double u = rng.uniform(), v = rng.uniform();
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        out.push_back(poly[0] + (poly[i] - poly[0]) * u + (poly[i + 1] - poly[0]) * v);
    }
    return out;
}

// A triangle facing `facing` (parallel, the same way) that contains p (within `tol` of its plane and of its edges),
// or -1.
int containingTriangle(const std::vector<Tri>& tris, const dvec3& p, const dvec3& facing, double tol) {
    const dvec3 f = glm::normalize(facing);
    for (size_t t = 0; t < tris.size(); ++t) {
        const Tri& tr = tris[t];
        const dvec3 n = tr.normal();
        const double len = glm::length(n);
        if (len == 0.0) continue;
        const dvec3 un = n / len;
        if (glm::dot(un, f) < 1.0 - 1e-6) continue;
        if (std::abs(glm::dot(p - tr.a, un)) > tol) continue;
        bool in = true;  // on the inner side of each edge, by tol
        const dvec3 v[3] = {tr.a, tr.b, tr.c};
        for (int e = 0; e < 3 && in; ++e) {
            const dvec3 edge = v[(e + 1) % 3] - v[e];
            const dvec3 inward = glm::normalize(glm::cross(un, edge));
            in = glm::dot(p - v[e], inward) >= -tol;
        }
        if (in) return int(t);
    }
    return -1;
}

// Every polygon is convex, lies on the union of the triangles, and turns counter-clockwise seen from the side they
// face; sorted largest first, at most maxPolygons, none below minPolygonShare.
void expectPolygonRules(const Mesh& mesh, const MeshOccluders& occ, const OccluderGenSettings& s, scenes::Rng& rng) {
    const std::vector<Tri> tris = trianglesOf(mesh);
    const Box bound = mesh.box();
    const dvec3 d = bound.max - bound.min;
    const double tol = toleranceOf(mesh), largestFace = std::max({d.x * d.y, d.y * d.z, d.z * d.x});
    EXPECT_FALSE(occ.closed);
    EXPECT_TRUE(occ.boxes.empty());
    EXPECT_LE(occ.polygons.size(), size_t(s.maxPolygons));
    for (size_t k = 0; k < occ.polygons.size(); ++k) {
        const auto& poly = occ.polygons[k];
        SCOPED_TRACE("polygon " + std::to_string(k) + " of " + std::to_string(poly.size()) + " corners");
        expectConvexPlanar(poly, tol);
        EXPECT_GE(area(poly), s.minPolygonShare * largestFace * (1.0 - 1e-9));
        if (k > 0) {
            EXPECT_GE(area(occ.polygons[k - 1]), area(poly) * (1.0 - 1e-9)) << "not largest first";
        }
        const dvec3 n = newellNormal(poly);
        for (const dvec3& p : samplesOf(poly, rng, 30)) {
            if (containingTriangle(tris, p, n, tol) >= 0) continue;
            ASSERT_LT(containingTriangle(tris, p, -n, tol), 0)
                << "turns clockwise seen from the side the triangles face";
            FAIL() << "point (" << p.x << " " << p.y << " " << p.z << ") on no triangle";
        }
    }
}

// --- Graphs.

void collectOccluders(Node* n, std::vector<Occluder*>& out) {
    if (n->kind() == NodeKind::Occluder) out.push_back(static_cast<Occluder*>(n));
    for (size_t i = 0; i < n->numChildren(); ++i) collectOccluders(n->child(i), out);
}
std::vector<Occluder*> occludersUnder(Node* n) {
    std::vector<Occluder*> out;
    collectOccluders(n, out);
    return out;
}

ref_ptr<Mesh> unitBoxMesh() { return makeBoxMesh(dvec3(-1), dvec3(1)); }
ref_ptr<Geometry> geometryOf(ref_ptr<Mesh> m, ref_ptr<Material> mat = make<Material>()) {
    return make<Geometry>(std::move(m), std::move(mat));
}

// A quad of side 2 in the plane z = 0, facing +z.
ref_ptr<Mesh> quadMesh() { return meshOf({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {0, 1, 2, 0, 2, 3}); }

}  // namespace

// --- 1. Boxes inside closed meshes.

TEST(GeneratedOccluders, ABoxMeshGetsABoxInsideIt) {
    scenes::Rng rng(1);
    for (int div : {1, 3}) {
        const ref_ptr<Mesh> m = makeBoxMesh(dvec3(-1, -2, -0.5), dvec3(3, 2, 1.5), div);
        ASSERT_TRUE(m->closed());
        const OccluderGenSettings s;
        const MeshOccluders occ = meshOccluders(*m, s);
        ASSERT_FALSE(occ.boxes.empty());
        expectBoxRules(*m, occ, s);
        expectInsideSolid(*m, occ.boxes, rng, "box div " + std::to_string(div));
        // A grid of 32 along the longest axis leaves at most a cell or two each side: most of the box.
        EXPECT_GT(volume(occ.boxes[0]), 0.5 * volume(m->box()));
    }
}

TEST(GeneratedOccluders, RotatedAndPlacedBoxesGetBoxesInside) {
    scenes::Rng rng(2);
    const OccluderGenSettings s = turned();
    for (int i = 0; i < 12; ++i) {
        const dvec3 half(rng.uniform(1.5, 3), rng.uniform(1.5, 3), rng.uniform(1.5, 3));
        const ref_ptr<Mesh> m = transformed(*makeBoxMesh(-half, half, 1 + rng.below(3)), randomPlacement(rng));
        ASSERT_TRUE(m->closed()) << "case " << i;
        const MeshOccluders occ = meshOccluders(*m, s);
        EXPECT_FALSE(occ.boxes.empty()) << "case " << i;
        expectBoxRules(*m, occ, s);
        expectInsideSolid(*m, occ.boxes, rng, "rotated box " + std::to_string(i));
    }
}

TEST(GeneratedOccluders, TorusBoxesAreInsideTheTube) {
    scenes::Rng rng(3);
    OccluderGenSettings s;
    s.minBoxShare = 0.005;  // boxes in a curved tube are small beside its bound
    s.maxBoxes = 8;
    // Tube radius 1.2 of a bound 8.4 wide: over 9 cells of 32 across the tube.
    const ref_ptr<Mesh> plain = torus(3.0, 1.2, 48, 24);
    ASSERT_TRUE(plain->closed());
    for (int i = 0; i < 4; ++i) {
        const ref_ptr<Mesh> m = i == 0 ? plain : transformed(*plain, randomPlacement(rng));
        ASSERT_TRUE(m->closed());
        const OccluderGenSettings si = i == 0 ? s : turned(s);
        const MeshOccluders occ = meshOccluders(*m, si);
        EXPECT_FALSE(occ.boxes.empty()) << "case " << i;
        expectBoxRules(*m, occ, si);
        expectInsideSolid(*m, occ.boxes, rng, "torus " + std::to_string(i));
    }
    // The hole: no box comes within the ring's inner radius of its axis.
    for (const Box& b : meshOccluders(*plain, s).boxes) {
        const dvec2 nearest(std::clamp(0.0, b.min.x, b.max.x), std::clamp(0.0, b.min.y, b.max.y));
        EXPECT_GE(glm::length(nearest), 1.8) << str(b);
    }
}

TEST(GeneratedOccluders, ConcaveShapesBoxesStayOutOfTheirNotches) {
    scenes::Rng rng(4);
    OccluderGenSettings s;
    s.maxBoxes = 8;
    const std::pair<const char*, ref_ptr<Mesh>> shapes[] = {
        {"L prism", lPrism()}, {"U", uShape()}, {"notched box", notchedBox()}, {"two boxes", twoBoxes()}};
    for (const auto& [name, plain] : shapes) {
        ASSERT_TRUE(plain->closed()) << name;
        for (int i = 0; i < 4; ++i) {
            const ref_ptr<Mesh> m = i == 0 ? plain : transformed(*plain, randomPlacement(rng));
            ASSERT_TRUE(m->closed()) << name;
            const OccluderGenSettings si = i == 0 ? s : turned(s);
            const MeshOccluders occ = meshOccluders(*m, si);
            EXPECT_FALSE(occ.boxes.empty()) << name << " case " << i;
            expectBoxRules(*m, occ, si);
            expectInsideSolid(*m, occ.boxes, rng, std::string(name) + " case " + std::to_string(i));
        }
    }
    // Axis-aligned, each part is a box of its own: two boxes in one mesh give a box in each.
    const ref_ptr<Mesh> two = twoBoxes();
    const MeshOccluders occ = meshOccluders(*two, s);
    bool left = false, right = false;
    for (const Box& b : occ.boxes) left |= b.max.x <= 3.0, right |= b.min.x >= 5.0;
    EXPECT_TRUE(left && right) << occ.boxes.size() << " boxes";
}

TEST(GeneratedOccluders, NestedAndOverlappingShellsBoxesAreInsideThem) {
    // Two closed shells, one inside the other or crossing it: the winding number is 2 where both enclose, and the
    // inner shell's faces cross the outer solid, where no box may pass through them.
    scenes::Rng rng(14);
    const ref_ptr<Mesh> outer = makeBoxMesh(dvec3(-3), dvec3(3));
    const std::pair<const char*, ref_ptr<Mesh>> shapes[] = {
        {"nested", merged(*outer, *makeBoxMesh(dvec3(-1), dvec3(1)))},
        {"crossing", merged(*outer, *makeBoxMesh(dvec3(1, -1, -1), dvec3(5, 1, 1)))},
        {"crossing tori",
         merged(*torus(3.0, 1.2, 32, 16),
                *transformed(*torus(3.0, 1.2, 32, 16), glm::rotate(dmat4(1.0), kPi / 2, dvec3(1, 0, 0))))}};
    OccluderGenSettings s;
    s.maxBoxes = 8;
    s.minBoxShare = 0.001;
    for (const auto& [name, m] : shapes) {
        ASSERT_TRUE(m->closed()) << name;
        const MeshOccluders occ = meshOccluders(*m, s);
        EXPECT_FALSE(occ.boxes.empty()) << name;
        expectBoxRules(*m, occ, s);
        expectInsideSolid(*m, occ.boxes, rng, name);
    }
}

TEST(GeneratedOccluders, RandomBlobsFarOffAndThinSlabsKeepTheBoxesInside) {
    // Random unions of lattice boxes (those whose boundary is closed: no cubes meeting along an edge alone, no
    // cavities), turned and placed, some far from the origin where float positions are coarse, over several grids.
    scenes::Rng rng(16);
    int tried = 0, withBoxes = 0;
    for (int blob = 0; tried < 24 && blob < 400; ++blob) {
        std::set<std::array<int, 3>> cells;  // a union of 2 to 4 lattice boxes, each at least 2 cubes wide
        for (int k = 0, n = 2 + rng.below(3); k < n; ++k) {
            int lo[3], hi[3];
            for (int a = 0; a < 3; ++a) lo[a] = rng.below(6), hi[a] = lo[a] + 2 + rng.below(4);
            for (int x = lo[0]; x < hi[0]; ++x)
                for (int y = lo[1]; y < hi[1]; ++y)
                    for (int z = lo[2]; z < hi[2]; ++z) cells.insert({x, y, z});
        }
        const ref_ptr<Mesh> plain = cellsMesh(cells, 0.5);
        if (cells.empty() || !plain->closed()) continue;
        ++tried;
        dmat4 xf = tried % 3 == 0 ? dmat4(1.0) : randomPlacement(rng);
        if (tried % 4 == 1) xf = glm::translate(dmat4(1.0), dvec3(3e4, -2e4, 1e4)) * xf;
        const ref_ptr<Mesh> m = transformed(*plain, xf);
        if (!m->closed()) continue;  // far off, float rounding may weld or split corners
        OccluderGenSettings s;
        s.voxels = 8u + 8u * uint32_t(rng.below(6));
        s.maxBoxes = 1u + uint32_t(rng.below(8));
        s.minBoxShare = 0.0;
        const MeshOccluders occ = meshOccluders(*m, s);
        withBoxes += !occ.boxes.empty();
        expectBoxRules(*m, occ, s);
        expectInsideSolid(*m, occ.boxes, rng, "blob " + std::to_string(blob) + " voxels " + std::to_string(s.voxels),
                          15, 20);
    }
    EXPECT_EQ(tried, 24);
    EXPECT_GE(withBoxes, 18) << "the blobs are several cells thick";
    // A slab thinner than a cell: no cell fits inside, so no box (or boxes inside it).
    for (double t : {0.05, 0.3, 0.6}) {
        const ref_ptr<Mesh> slab = transformed(*makeBoxMesh(dvec3(-5, -5, 0), dvec3(5, 5, t)), randomPlacement(rng));
        OccluderGenSettings s;
        s.minBoxShare = 0.0;
        s.maxBoxes = 16;
        const MeshOccluders occ = meshOccluders(*slab, s);
        expectBoxRules(*slab, occ, s);
        expectInsideSolid(*slab, occ.boxes, rng, "slab " + std::to_string(t));
    }
}

TEST(GeneratedOccluders, SphereBoxesAreInsideIt) {
    scenes::Rng rng(5);
    OccluderGenSettings s;
    s.maxBoxes = 6;
    const ref_ptr<Mesh> plain = uvSphere(2.0, 16, 32);
    ASSERT_TRUE(plain->closed());
    for (int i = 0; i < 4; ++i) {
        const ref_ptr<Mesh> m = i == 0 ? plain : transformed(*plain, randomPlacement(rng));
        ASSERT_TRUE(m->closed());
        const OccluderGenSettings si = i == 0 ? s : turned(s);
        const MeshOccluders occ = meshOccluders(*m, si);
        EXPECT_FALSE(occ.boxes.empty()) << "case " << i;
        expectBoxRules(*m, occ, si);
        expectInsideSolid(*m, occ.boxes, rng, "sphere " + std::to_string(i));
    }
}

TEST(GeneratedOccluders, GridSizesAndBoxCountsKeepTheBoxesInside) {
    scenes::Rng rng(6);
    const ref_ptr<Mesh> shapes[] = {notchedBox(), torus(2.0, 0.8, 32, 16), uvSphere(1.0, 12, 24)};
    for (uint32_t voxels : {1u, 2u, 5u, 17u, 64u})
        for (uint32_t maxBoxes : {0u, 1u, 3u, 16u})
            for (size_t k = 0; k < std::size(shapes); ++k) {
                OccluderGenSettings s;
                s.voxels = voxels;
                s.maxBoxes = maxBoxes;
                s.minBoxShare = 0.0;
                const MeshOccluders occ = meshOccluders(*shapes[k], s);
                expectBoxRules(*shapes[k], occ, s);
                expectInsideSolid(*shapes[k], occ.boxes, rng,
                                  "shape " + std::to_string(k) + " voxels " + std::to_string(voxels) + " maxBoxes " +
                                      std::to_string(maxBoxes),
                                  10, 20);
            }
}

TEST(GeneratedOccluders, SameMeshSameBoxes) {
    const ref_ptr<Mesh> m = torus(3.0, 1.2, 40, 20);
    const MeshOccluders a = meshOccluders(*m), b = meshOccluders(*m);
    ASSERT_EQ(a.boxes.size(), b.boxes.size());
    for (size_t k = 0; k < a.boxes.size(); ++k) {
        EXPECT_EQ(a.boxes[k].min, b.boxes[k].min);
        EXPECT_EQ(a.boxes[k].max, b.boxes[k].max);
    }
    EXPECT_EQ(a.voxelsInside, b.voxelsInside);
}

TEST(GeneratedOccluders, OpenMeshesGetNoBoxes) {
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1), dvec3(1), 2);
    const ref_ptr<Mesh> lidless = withoutTriangles(*box, 8, 8);  // the +z face: triangles 8..15 with div 2
    ASSERT_FALSE(lidless->closed());
    MeshOccluders occ = meshOccluders(*lidless);
    EXPECT_FALSE(occ.closed);
    EXPECT_TRUE(occ.boxes.empty());
    EXPECT_EQ(occ.voxelsInside, 0u);

    const ref_ptr<Mesh> t = torus(3.0, 1.2, 48, 24);
    const ref_ptr<Mesh> pierced = withoutTriangles(*t, 100, 2);  // one quad gone
    ASSERT_FALSE(pierced->closed());
    occ = meshOccluders(*pierced);
    EXPECT_FALSE(occ.closed);
    EXPECT_TRUE(occ.boxes.empty());

    // One triangle gone from a sphere, and a sphere turned inside out: not closed either.
    const ref_ptr<Mesh> sphere = uvSphere(2.0, 16, 32);
    EXPECT_TRUE(meshOccluders(*withoutTriangles(*sphere, 40, 1)).boxes.empty());
    std::vector<uint32_t> idx = indicesOf(*sphere);
    for (size_t i = 0; i < idx.size(); i += 3) std::swap(idx[i + 1], idx[i + 2]);
    std::vector<dvec3> pos;
    for (const vec3& p : sphere->positions()) pos.push_back(dvec3(p));
    const ref_ptr<Mesh> insideOut = meshOf(pos, idx);
    ASSERT_FALSE(insideOut->closed());
    EXPECT_TRUE(meshOccluders(*insideOut).boxes.empty());
}

// --- 2. Polygons on open meshes.

TEST(GeneratedOccluders, AQuadGivesItself) {
    scenes::Rng rng(7);
    const dmat4 placements[] = {dmat4(1.0), randomPlacement(rng), randomPlacement(rng)};
    for (size_t i = 0; i < std::size(placements); ++i) {
        SCOPED_TRACE(i == 0 ? "in place" : "placement " + std::to_string(i) + " (turned, float positions)");
        const dmat4& xf = placements[i];
        const ref_ptr<Mesh> quad = transformed(*quadMesh(), xf);
        const OccluderGenSettings s;
        const MeshOccluders occ = meshOccluders(*quad, s);
        expectPolygonRules(*quad, occ, s, rng);
        ASSERT_EQ(occ.polygons.size(), 1u);
        const auto& poly = occ.polygons[0];
        ASSERT_EQ(poly.size(), 4u);
        const std::vector<Tri> tris = trianglesOf(*quad);
        EXPECT_NEAR(area(poly), 0.5 * (glm::length(tris[0].normal()) + glm::length(tris[1].normal())),
                    1e-5 * area(poly));
        EXPECT_GT(glm::dot(newellNormal(poly), tris[0].normal()), 0.0) << "clockwise seen from the front";
        for (const vec3& corner : quad->positions()) {
            double nearest = kInf;
            for (const dvec3& v : poly) nearest = std::min(nearest, glm::length(v - dvec3(corner)));
            EXPECT_LT(nearest, toleranceOf(*quad)) << "a corner of the quad missing";
        }
    }
}

TEST(GeneratedOccluders, AnOpenBoxGivesItsFaces) {
    scenes::Rng rng(8);
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1, -1, -1), dvec3(1, 1, 1), 1);
    const ref_ptr<Mesh> lidless = withoutTriangles(*box, 2, 2);  // the +z face
    ASSERT_FALSE(lidless->closed());
    // (Its opening capped, it gets a box instead: CappedOccludersTest.cpp.)
    OccluderGenSettings s;
    s.capOpenings = false;
    const MeshOccluders occ = meshOccluders(*lidless, s);
    expectPolygonRules(*lidless, occ, s, rng);
    ASSERT_EQ(occ.polygons.size(), 5u);
    for (const auto& poly : occ.polygons) EXPECT_NEAR(area(poly), 4.0, 1e-5);

    // Faces split into 3 x 3 quads, placed anywhere: polygons on the faces, at least one quad of 2/3 x 2/3 large
    // (the two triangles of a quad are coplanar up to the rounding of their float positions).
    OccluderGenSettings any = s;
    any.minPolygonShare = 0.0;
    for (int i = 0; i < 4; ++i) {
        SCOPED_TRACE(i == 0 ? "in place" : "placement " + std::to_string(i) + " (turned, float positions)");
        const ref_ptr<Mesh> m = transformed(*withoutTriangles(*makeBoxMesh(dvec3(-1), dvec3(1), 3), 18, 18),
                                            i == 0 ? dmat4(1.0) : randomPlacement(rng));
        const MeshOccluders o = meshOccluders(*m, any);
        expectPolygonRules(*m, o, any, rng);
        ASSERT_FALSE(o.polygons.empty());
        const double quad = glm::length(trianglesOf(*m)[0].normal());  // two triangles of a quad
        EXPECT_GE(area(o.polygons[0]), quad * (1.0 - 1e-5));
    }
}

TEST(GeneratedOccluders, AnLShapedRegionGivesConvexPolygonsInsideIt) {
    scenes::Rng rng(9);
    // Three unit squares in z = 0 making an L: (0,0), (1,0), (0,1); corners on a 3 x 3 lattice.
    auto v = [](int x, int y) { return uint32_t(y * 3 + x); };
    std::vector<dvec3> pos;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) pos.push_back(dvec3(x, y, 0));
    std::vector<uint32_t> idx;
    for (auto [x, y] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{0, 1}})
        idx.insert(idx.end(), {v(x, y), v(x + 1, y), v(x + 1, y + 1), v(x, y), v(x + 1, y + 1), v(x, y + 1)});
    const ref_ptr<Mesh> plain = meshOf(pos, idx);
    for (int i = 0; i < 4; ++i) {
        SCOPED_TRACE(i == 0 ? "in place" : "placement " + std::to_string(i) + " (turned, float positions)");
        const ref_ptr<Mesh> m = i == 0 ? plain : transformed(*plain, randomPlacement(rng));
        const OccluderGenSettings s;
        const MeshOccluders occ = meshOccluders(*m, s);
        expectPolygonRules(*m, occ, s, rng);
        ASSERT_FALSE(occ.polygons.empty());
        const double cell = glm::length(trianglesOf(*m)[0].normal());  // one square: two triangles
        EXPECT_GE(area(occ.polygons[0]), cell * (1.0 - 1e-5));
        EXPECT_LT(area(occ.polygons[0]), 2.9 * cell) << "the whole L is not convex";
    }
}

TEST(GeneratedOccluders, ACurvedSurfaceGivesNoLargePolygon) {
    scenes::Rng rng(10);
    const ref_ptr<Mesh> dome = uvSphere(1.0, 32, 48, true);
    ASSERT_FALSE(dome->closed());
    OccluderGenSettings s;
    s.capOpenings = false;  // capped, it gets boxes instead (CappedOccludersTest.cpp)
    EXPECT_TRUE(meshOccluders(*dome, s).polygons.empty());
    // Without a threshold: nothing larger than a quad of the UV grid (its two triangles are coplanar).
    s.minPolygonShare = 0.0;
    const MeshOccluders occ = meshOccluders(*dome, s);
    expectPolygonRules(*dome, occ, s, rng);
    double largestTriangle = 0.0;
    for (const Tri& t : trianglesOf(*dome)) largestTriangle = std::max(largestTriangle, 0.5 * glm::length(t.normal()));
    for (const auto& poly : occ.polygons) EXPECT_LE(area(poly), 2.0 * largestTriangle * (1.0 + 1e-6));
}

TEST(GeneratedOccluders, NonFiniteOrEmptyMeshesGiveNothing) {
    for (double bad : {kNaN, kInf, -kInf}) {
        const ref_ptr<Mesh> quad = meshOf({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, bad}}, {0, 1, 2, 0, 2, 3});
        MeshOccluders occ = meshOccluders(*quad);
        EXPECT_TRUE(occ.polygons.empty() && occ.boxes.empty());
        std::vector<dvec3> pos;
        const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1), dvec3(1));  // held: the loop reads its positions
        for (const vec3& p : box->positions()) pos.push_back(dvec3(p));
        pos[5].y = bad;
        occ = meshOccluders(*meshOf(pos, indicesOf(*box)));
        EXPECT_TRUE(occ.polygons.empty() && occ.boxes.empty());
    }
    const MeshOccluders occ = meshOccluders(*make<Mesh>());
    EXPECT_TRUE(occ.polygons.empty() && occ.boxes.empty());
}

// --- 3. Occluder nodes in a graph.

TEST(GeneratedOccluders, AGeometryGetsABoxBesideIt) {
    scenes::Rng rng(11);
    auto root = make<Group>();
    auto g = geometryOf(makeBoxMesh(dvec3(-1, -2, -3), dvec3(2, 1, 0)));
    root->addChild(g);
    const OccluderGenStats st = generateOccluders(*root);
    ASSERT_EQ(root->numChildren(), 2u);
    const std::vector<Occluder*> occ = occludersUnder(root.get());
    ASSERT_EQ(occ.size(), 1u);
    EXPECT_LT(root->indexOf(occ[0]), 2u) << "not beside the geometry";
    EXPECT_TRUE(occ[0]->generated());
    EXPECT_EQ(occ[0]->shape(), Occluder::Shape::Box);
    EXPECT_EQ(occ[0]->shownWith(), nullptr);
    expectInsideSolid(*g->mesh(), {occ[0]->box()}, rng, "beside a geometry");
    // An eye inside the solid must not use it: the box it is used outside of covers the whole mesh.
    ASSERT_FALSE(occ[0]->eyeOutside().empty());
    EXPECT_TRUE(occ[0]->eyeOutside().contains(g->mesh()->box().min) &&
                occ[0]->eyeOutside().contains(g->mesh()->box().max))
        << str(occ[0]->eyeOutside());
    EXPECT_EQ(st.geometries, 1u);
    EXPECT_EQ(st.meshes, 1u);
    EXPECT_EQ(st.meshTriangles, 12u);
    EXPECT_EQ(st.sceneTriangles, 12u);
    EXPECT_EQ(st.boxes, 1u);
    EXPECT_EQ(st.polygons, 0u);
    EXPECT_EQ(st.lods, 0u);
    EXPECT_EQ(st.skipped, 0u);
}

TEST(GeneratedOccluders, AnOpenGeometryGetsPolygons) {
    auto root = make<Group>();
    auto single = make<Material>();
    single->doubleSided = false;
    root->addChild(geometryOf(quadMesh(), single));
    const OccluderGenStats st = generateOccluders(*root);
    const std::vector<Occluder*> occ = occludersUnder(root.get());
    ASSERT_EQ(occ.size(), 1u);
    EXPECT_TRUE(occ[0]->generated());
    EXPECT_EQ(occ[0]->shape(), Occluder::Shape::Polygon);
    EXPECT_NEAR(area(occ[0]->polygon()), 4.0, 1e-5);
    EXPECT_TRUE(occ[0]->oneSided()) << "back faces are not drawn: the polygon hides nothing seen from behind";
    EXPECT_EQ(st.polygons, 1u);
    EXPECT_EQ(st.boxes, 0u);
}

TEST(GeneratedOccluders, APolygonWithinABoxedMeshBesideItIsLeftOut) {
    // A floor inside a building (a closed box), a roof slab on top of it (within the bound's tolerance), and a wall
    // beside it reaching out of the bound: the first two are left out, the wall is kept.
    auto root = make<Group>();
    root->addChild(geometryOf(makeBoxMesh(dvec3(-4, -4, 0), dvec3(4, 4, 6))));
    auto floorAt = [](double z) {
        return meshOf({{-3, -3, z}, {3, -3, z}, {3, 3, z}, {-3, 3, z}}, {0, 1, 2, 0, 2, 3});
    };
    root->addChild(geometryOf(floorAt(3.0)));
    root->addChild(geometryOf(floorAt(6.0)));
    root->addChild(geometryOf(meshOf({{5, -4, 0}, {5, 4, 0}, {5, 4, 6}, {5, -4, 6}}, {0, 1, 2, 0, 2, 3})));
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(st.boxes, 1u);
    EXPECT_EQ(st.polygons, 1u);
    EXPECT_EQ(st.enclosed, 2u);
    const std::vector<Occluder*> occ = occludersUnder(root.get());
    size_t polygons = 0;
    for (const Occluder* o : occ)
        if (o->shape() == Occluder::Shape::Polygon) {
            ++polygons;
            for (const dvec3& v : o->polygon()) EXPECT_NEAR(v.x, 5.0, 1e-6) << "the wall outside the bound is kept";
        }
    EXPECT_EQ(polygons, 1u);

    // In another group the box's bound does not count: the floor is kept.
    auto other = make<Group>();
    auto inner = make<Group>();
    other->addChild(geometryOf(makeBoxMesh(dvec3(-4, -4, 0), dvec3(4, 4, 6))));
    inner->addChild(geometryOf(floorAt(3.0)));
    other->addChild(inner);
    const OccluderGenStats st2 = generateOccluders(*other);
    EXPECT_EQ(st2.polygons, 1u);
    EXPECT_EQ(st2.enclosed, 0u);
}

TEST(GeneratedOccluders, BlendedOrMaskedMaterialsGetNone) {
    auto blended = make<Material>();
    blended->blend = true;
    auto cutout = make<Material>();
    cutout->alphaCutoff = 0.5f;
    for (const auto& mat : {blended, cutout}) {
        auto root = make<Group>();
        root->addChild(geometryOf(unitBoxMesh(), mat));
        root->addChild(geometryOf(quadMesh(), mat));
        const OccluderGenStats st = generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty());
        EXPECT_EQ(root->numChildren(), 2u);
        EXPECT_EQ(st.geometries, 0u);
        EXPECT_EQ(st.skipped, 2u);
    }
}

TEST(GeneratedOccluders, GeometryThePassWouldNotUseGetsNone) {
    {
        auto root = make<Group>();
        auto sw = make<Switch>();
        sw->addChild(geometryOf(unitBoxMesh()), true);
        root->addChild(sw);
        const OccluderGenStats st = generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "under a Switch";
        EXPECT_EQ(st.skipped, 1u);
    }
    {
        auto root = make<Group>();
        auto bb = make<Billboard>();
        bb->addChild(geometryOf(unitBoxMesh()));
        root->addChild(bb);
        generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "under a Billboard";
    }
    {
        auto root = make<Group>();
        // A masked Geometry gets none (the occluder beside it would not carry its mask); below a masked Group, the
        // occluder carries the Group's mask as the pass's condition, so it is made.
        auto masked = make<Group>();
        masked->setNodeMask(0x1);
        auto g = geometryOf(unitBoxMesh());
        g->setNodeMask(0x1);
        masked->addChild(g);
        root->addChild(masked);
        generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "a masked Geometry";
        g->setNodeMask(0xffffffffu);
        generateOccluders(*root);
        EXPECT_EQ(occludersUnder(root.get()).size(), 1u) << "below a masked Group";
    }
    {
        auto root = make<Group>();
        auto proto = make<Group>();
        proto->addChild(geometryOf(unitBoxMesh()));
        root->addChild(make<Instance>(proto, glm::translate(dmat4(1.0), dvec3(5, 0, 0))));
        generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "in an Instance's prototype";
        EXPECT_EQ(proto->numChildren(), 1u);
    }
}

TEST(GeneratedOccluders, AnAuthoredOccluderIsKeptAndNoneAdded) {
    auto root = make<Group>();
    auto authored = make<Occluder>();
    authored->setBox(Box{dvec3(-0.5), dvec3(0.5)});
    root->addChild(authored);
    root->addChild(geometryOf(unitBoxMesh()));
    auto other = make<Group>();  // a parent without one still gets its own
    other->addChild(geometryOf(unitBoxMesh()));
    root->addChild(other);
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(root->numChildren(), 3u);
    EXPECT_EQ(root->child(0), authored.get());
    EXPECT_FALSE(authored->generated());
    EXPECT_EQ(other->numChildren(), 2u);
    EXPECT_EQ(occludersUnder(root.get()).size(), 2u);
    EXPECT_EQ(st.skipped, 1u);
    EXPECT_EQ(st.geometries, 1u);
}

TEST(GeneratedOccluders, AnLodGetsABoxInsideEveryLevel) {
    scenes::Rng rng(12);
    auto root = make<Group>();
    auto lod = make<LOD>();
    const ref_ptr<Mesh> fine = makeBoxMesh(dvec3(-2, -2, -2), dvec3(2, 2, 2), 2);
    const ref_ptr<Mesh> coarse = makeBoxMesh(dvec3(-1.5, -1, -2.5), dvec3(1, 2.5, 1.2));
    lod->addChild(geometryOf(fine), 0.0f, 50.0f);
    lod->addChild(geometryOf(coarse), 50.0f, 500.0f);
    root->addChild(geometryOf(quadMesh()));
    root->addChild(lod);
    root->addChild(geometryOf(makeBoxMesh(dvec3(10), dvec3(11))));
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(lod->numChildren(), 2u) << "the LOD's levels are its children: nothing may be added among them";
    const size_t at = root->indexOf(lod.get());
    ASSERT_LT(at + 1, root->numChildren());
    ASSERT_EQ(root->child(at + 1)->kind(), NodeKind::Occluder) << "the pass finds the LOD as the sibling before";
    std::vector<Occluder*> withLod;
    for (Occluder* o : occludersUnder(root.get()))
        if (o->shownWith() == lod.get()) withLod.push_back(o);
    ASSERT_FALSE(withLod.empty());
    for (Occluder* o : withLod) {
        EXPECT_TRUE(o->generated());
        ASSERT_EQ(o->shape(), Occluder::Shape::Box);
        EXPECT_EQ(root->indexOf(o), at + 1) << "only the sibling right after the LOD is used with it";
        expectInsideSolid(*fine, {o->box()}, rng, "fine level");
        expectInsideSolid(*coarse, {o->box()}, rng, "coarse level");
        // An eye inside the level shown must not use it: the box it is used outside of covers every level.
        const Box& eye = o->eyeOutside();
        ASSERT_FALSE(eye.empty());
        for (const Mesh* m : {fine.get(), coarse.get()})
            EXPECT_TRUE(eye.contains(m->box().min) && eye.contains(m->box().max)) << str(eye);
    }
    EXPECT_EQ(st.lods, withLod.size());
}

TEST(GeneratedOccluders, EveryBoxOfAnLodStandsRightAfterIt) {
    // Levels shaped as an L give a box in each arm: each box must follow the LOD (other occluders between) to be used
    // with it (Occluder::setShownWith), which the image records as the LOD's entry.
    scenes::Rng rng(15);
    auto root = make<Group>();
    auto lod = make<LOD>();
    const ref_ptr<Mesh> fine = lPrism();
    const ref_ptr<Mesh> coarse =
        transformed(*lPrism(), glm::translate(dmat4(1.0), dvec3(3, 3, 1)) * glm::scale(dmat4(1.0), dvec3(1.05)) *
                                   glm::translate(dmat4(1.0), dvec3(-3, -3, -1)));
    lod->addChild(geometryOf(fine), 0.0f, 50.0f);
    lod->addChild(geometryOf(coarse), 50.0f, 500.0f);
    root->addChild(lod);
    OccluderGenSettings s;
    s.maxBoxes = 4;
    generateOccluders(*root, s);
    std::vector<Occluder*> withLod;
    for (Occluder* o : occludersUnder(root.get()))
        if (o->shownWith() == lod.get()) withLod.push_back(o);
    ASSERT_FALSE(withLod.empty());
    for (Occluder* o : withLod) {
        expectInsideSolid(*fine, {o->box()}, rng, "fine L");
        expectInsideSolid(*coarse, {o->box()}, rng, "coarse L");
        // After the LOD, with only occluders between them: the image finds the LOD for each.
        for (size_t k = root->indexOf(lod.get()) + 1; k < root->indexOf(o); ++k)
            EXPECT_EQ(root->child(k)->kind(), NodeKind::Occluder) << "something other than an occluder between";
        EXPECT_GT(root->indexOf(o), root->indexOf(lod.get()));
    }
    Scene scene(root);
    scene.update();
    for (const FlatImage::OccluderRef& ref : scene.image().occluders) {
        if (static_cast<const Occluder*>(ref.node)->shownWith() != lod.get()) continue;
        EXPECT_TRUE(ref.active && ref.lod != ~0u) << "an occluder of the LOD the pass never uses";
    }
}

TEST(GeneratedOccluders, AnLodWithAnOpenLevelOrLevelsApartGetsNoBox) {
    for (int k = 0; k < 2; ++k) {
        auto root = make<Group>();
        auto lod = make<LOD>();
        lod->addChild(geometryOf(unitBoxMesh()), 0.0f, 50.0f);
        lod->addChild(geometryOf(k == 0 ? quadMesh() : makeBoxMesh(dvec3(5), dvec3(7))), 50.0f, 500.0f);
        root->addChild(lod);
        const OccluderGenStats st = generateOccluders(*root);
        for (Occluder* o : occludersUnder(root.get())) EXPECT_NE(o->shownWith(), lod.get()) << "case " << k;
        EXPECT_EQ(st.lods, 0u);
        EXPECT_EQ(lod->numChildren(), 2u);
    }
}

TEST(GeneratedOccluders, RunningAgainAddsNoDuplicatesAndRemoveTakesOnlyGenerated) {
    auto root = make<Group>();
    for (int i = 0; i < 5; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(4.0 * i, 0, 0)));
        t->addChild(geometryOf(unitBoxMesh()));
        t->addChild(geometryOf(quadMesh()));
        root->addChild(t);
    }
    auto withAuthored = make<Group>();
    auto authored = make<Occluder>();
    authored->setBox(Box{dvec3(20), dvec3(21)});
    withAuthored->addChild(authored);
    withAuthored->addChild(geometryOf(unitBoxMesh()));
    root->addChild(withAuthored);

    const OccluderGenStats first = generateOccluders(*root);
    const size_t count = occludersUnder(root.get()).size();
    ASSERT_GT(count, 5u);
    EXPECT_EQ(first.boxes + first.polygons + 1, count);
    const OccluderGenStats second = generateOccluders(*root);
    EXPECT_EQ(occludersUnder(root.get()).size(), count);
    EXPECT_EQ(second.boxes, first.boxes);
    EXPECT_EQ(second.polygons, first.polygons);

    EXPECT_EQ(removeOccluders(*root, true), count - 1);
    const std::vector<Occluder*> left = occludersUnder(root.get());
    ASSERT_EQ(left.size(), 1u);
    EXPECT_EQ(left[0], authored.get());
    for (size_t i = 0; i < 5; ++i) EXPECT_EQ(root->child(i)->numChildren(), 2u);

    generateOccluders(*root);
    EXPECT_EQ(occludersUnder(root.get()).size(), count);
    EXPECT_EQ(removeOccluders(*root, false), count);
    EXPECT_TRUE(occludersUnder(root.get()).empty());
}

TEST(GeneratedOccluders, TheOccluderIsInTheGeometrysFrame) {
    scenes::Rng rng(13);
    for (int i = 0; i < 4; ++i) {
        const dmat4 xf = randomPlacement(rng) * glm::scale(dmat4(1.0), dvec3(1.0, 2.0, 0.5));
        const ref_ptr<Mesh> mesh = lPrism();
        auto root = make<Group>();
        auto t = make<Transform>(xf);
        t->addChild(geometryOf(mesh));
        root->addChild(t);
        generateOccluders(*root);
        const std::vector<Occluder*> occ = occludersUnder(root.get());
        ASSERT_FALSE(occ.empty());
        for (Occluder* o : occ) EXPECT_EQ(t->indexOf(o) < t->numChildren(), true) << "not beside the geometry";

        Box world;  // the transformed mesh's bound, exactly
        for (const vec3& p : mesh->positions()) world.expand(dvec3(xf * dvec4(dvec3(p), 1.0)));
        const std::vector<Tri> worldTris = trianglesOf(*transformed(*mesh, xf));
        Scene scene(root);
        scene.update();
        const FlatImage& img = scene.image();
        ASSERT_EQ(img.occluders.size(), occ.size());
        const double slack = 1e-5 * (glm::length(world.max) + glm::length(world.max - world.min));
        for (const FlatImage::OccluderRef& ref : img.occluders) {
            EXPECT_TRUE(ref.active);
            const Box b = img.box(ref.entry);
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(b.min, world.min - slack)) &&
                        glm::all(glm::lessThanEqual(b.max, world.max + slack)))
                << "world box " << str(b) << " outside the mesh's world bound " << str(world);
            const Box local = static_cast<const Occluder*>(ref.node)->box();
            for (int c = 0; c < 8; ++c) {
                const dvec3 corner(c & 1 ? local.max.x : local.min.x, c & 2 ? local.max.y : local.min.y,
                                   c & 4 ? local.max.z : local.min.z);
                EXPECT_GT(windingNumber(worldTris, dvec3(xf * dvec4(corner, 1.0))), 0.5) << "corner " << c;
            }
        }
    }
}

TEST(GeneratedOccluders, AMeshSharedByManyGeometriesIsAnalysedOnce) {
    auto root = make<Group>();
    const ref_ptr<Mesh> mesh = makeBoxMesh(dvec3(-1), dvec3(1), 2);
    auto mat = make<Material>();
    for (int i = 0; i < 100; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(3.0 * (i % 10), 3.0 * (i / 10), 0)));
        t->addChild(geometryOf(mesh, mat));
        root->addChild(t);
    }
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(st.meshes, 1u);
    EXPECT_EQ(st.meshTriangles, uint64_t(mesh->triangleCount()));
    EXPECT_EQ(st.sceneTriangles, 100u * mesh->triangleCount());
    EXPECT_EQ(st.geometries, 100u);
    EXPECT_EQ(st.boxes, 100u);
    EXPECT_EQ(st.skipped, 0u);
    EXPECT_GE(st.ms, 0.0);
    EXPECT_EQ(occludersUnder(root.get()).size(), 100u);
    Box first;
    for (size_t i = 0; i < 100; ++i) {
        const Node* t = root->child(i);
        ASSERT_EQ(t->numChildren(), 2u);
        const Node* o = t->child(0)->kind() == NodeKind::Occluder ? t->child(0) : t->child(1);
        ASSERT_EQ(o->kind(), NodeKind::Occluder);
        const Box b = static_cast<const Occluder*>(o)->box();
        if (i == 0) first = b;
        EXPECT_EQ(b.min, first.min);
        EXPECT_EQ(b.max, first.max);
    }
}

TEST(GeneratedOccluders, StatsCountGeometryNodes) {
    // Three geometries under a Switch are three left without; a small box beside a large one is left out as minor,
    // and its geometry did not get an occluder.
    auto root = make<Group>();
    auto sw = make<Switch>();
    for (int i = 0; i < 3; ++i) sw->addChild(geometryOf(unitBoxMesh()), true);
    root->addChild(sw);
    root->addChild(make<Switch>());  // no geometry: nothing left without
    auto big = make<Group>();
    big->addChild(geometryOf(makeBoxMesh(dvec3(0), dvec3(100))));
    root->addChild(big);
    auto small = make<Group>();
    small->addChild(geometryOf(makeBoxMesh(dvec3(200), dvec3(201))));
    root->addChild(small);
    OccluderGenSettings s;
    s.minMajorShare = 0.1;
    const OccluderGenStats st = generateOccluders(*root, s);
    EXPECT_EQ(small->numChildren(), 1u) << "a 1-unit box beside a 100-unit one is minor";
    EXPECT_EQ(big->numChildren(), 2u);
    EXPECT_EQ(st.minor, 1u);
    EXPECT_EQ(st.boxes, 1u);
    EXPECT_EQ(st.skipped, 3u) << "Geometry nodes left without";
    EXPECT_EQ(st.geometries, 1u) << "Geometry nodes that got occluders";
}

// --- 4. Bad settings.

namespace {
void expectRejected(const OccluderGenSettings& s, const std::string& setting) {
    try {
        s.validate("sg::generateOccluders()");
        ADD_FAILURE() << setting << ": accepted";
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("sg::generateOccluders()"), std::string::npos) << msg;
        EXPECT_NE(msg.find(setting), std::string::npos) << msg;
    }
}
}  // namespace

TEST(GeneratedOccluders, BadSettingsAreRejectedByName) {
    OccluderGenSettings s;
    EXPECT_NO_THROW(s.validate("f"));
    s.voxels = 0;
    expectRejected(s, "voxels");
    s.voxels = 1000;
    expectRejected(s, "voxels");
    s.voxels = 257;
    expectRejected(s, "voxels");
    s = {};
    s.voxels = 256;
    EXPECT_NO_THROW(s.validate("f"));
    s = {};
    s.minBoxShare = 1.5;
    expectRejected(s, "minBoxShare");
    s.minBoxShare = kNaN;
    expectRejected(s, "minBoxShare");
    s.minBoxShare = -0.1;
    expectRejected(s, "minBoxShare");
    s = {};
    s.minPolygonShare = 1.5;
    expectRejected(s, "minPolygonShare");
    s.minPolygonShare = kNaN;
    expectRejected(s, "minPolygonShare");
    s = {};
    s.minMajorShare = 2.0;
    expectRejected(s, "minMajorShare");
    s.minMajorShare = kNaN;
    expectRejected(s, "minMajorShare");
    s = {};
    s.maxBoxes = 65;
    expectRejected(s, "maxBoxes");
    s = {};
    s.maxPolygons = 65;
    expectRejected(s, "maxPolygons");
    s = {};
    s.maxOpenings = 65;
    expectRejected(s, "maxOpenings");
    s = {};
    s.openingDepth = -0.01;
    expectRejected(s, "openingDepth");
    s.openingDepth = kNaN;
    expectRejected(s, "openingDepth");
    s.openingDepth = 1.5;
    expectRejected(s, "openingDepth");
    s = {};
    s.minBoxShare = 1.0;
    s.minPolygonShare = 0.0;
    s.maxOpenings = 64;
    s.openingDepth = 1.0;
    s.maxBoxes = 64;
    s.maxPolygons = 0;
    EXPECT_NO_THROW(s.validate("f"));
}

TEST(GeneratedOccluders, GenerateRejectsBadSettingsBeforeChangingTheGraph) {
    auto root = make<Group>();
    root->addChild(geometryOf(unitBoxMesh()));
    OccluderGenSettings s;
    s.voxels = 0;
    EXPECT_THROW(generateOccluders(*root, s), std::invalid_argument);
    EXPECT_EQ(root->numChildren(), 1u);
    EXPECT_THROW(meshOccluders(*unitBoxMesh(), s), std::invalid_argument);
}
