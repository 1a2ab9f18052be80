// MeshOccluders: boxes inside closed meshes (checked against the solid with a winding number, ray parity, a
// triangle-box overlap test and rays from outside, all computed here in double precision) and convex polygons on the
// faces of open ones.
#include "sg/build/GeneratedOccluders.h"

#include "build/OccluderChecks.h"
#include "testbed/Rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace sg;
using namespace occtest;

namespace {

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

// The boxes of a closed mesh that must get some, checked against the count, order and size rules.
MeshOccluders boxesOf(const Mesh& mesh, const OccluderGenSettings& s, const std::string& what) {
    MeshOccluders occ = meshOccluders(mesh, s);
    EXPECT_FALSE(occ.boxes.empty()) << what;
    expectBoxRules(mesh, occ, s);
    return occ;
}

// A closed mesh as it is and turned three random ways: boxes in each (a finer grid once turned), inside its solid.
void expectBoxesInsideTurned(const ref_ptr<Mesh>& plain, const OccluderGenSettings& s, scenes::Rng& rng,
                             const std::string& what) {
    for (int i = 0; i < 4; ++i) {
        const ref_ptr<Mesh> m = i == 0 ? plain : transformed(*plain, randomPlacement(rng));
        ASSERT_TRUE(m->closed());
        const OccluderGenSettings si = i == 0 ? s : turned(s);
        const MeshOccluders occ = boxesOf(*m, si, what + " case " + std::to_string(i));
        expectInsideSolid(*m, occ.boxes, rng, what + " " + std::to_string(i));
    }
}

// --- Polygons.

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

}  // namespace

// --- 1. Boxes inside closed meshes.

TEST(MeshOccluders, ABoxMeshGetsABoxInsideIt) {
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

TEST(MeshOccluders, RotatedAndPlacedBoxesGetBoxesInside) {
    scenes::Rng rng(2);
    const OccluderGenSettings s = turned();
    for (int i = 0; i < 12; ++i) {
        const dvec3 half(rng.uniform(1.5, 3), rng.uniform(1.5, 3), rng.uniform(1.5, 3));
        const ref_ptr<Mesh> m = transformed(*makeBoxMesh(-half, half, 1 + rng.below(3)), randomPlacement(rng));
        ASSERT_TRUE(m->closed()) << "case " << i;
        const MeshOccluders occ = boxesOf(*m, s, "case " + std::to_string(i));
        expectInsideSolid(*m, occ.boxes, rng, "rotated box " + std::to_string(i));
    }
}

TEST(MeshOccluders, TorusBoxesAreInsideTheTube) {
    scenes::Rng rng(3);
    OccluderGenSettings s;
    s.minBoxShare = 0.005;  // boxes in a curved tube are small beside its bound
    s.maxBoxes = 8;
    // Tube radius 1.2 of a bound 8.4 wide: over 9 cells of 32 across the tube.
    const ref_ptr<Mesh> plain = torus(3.0, 1.2, 48, 24);
    ASSERT_TRUE(plain->closed());
    expectBoxesInsideTurned(plain, s, rng, "torus");
    // The hole: no box comes within the ring's inner radius of its axis.
    for (const Box& b : meshOccluders(*plain, s).boxes) {
        const dvec2 nearest(std::clamp(0.0, b.min.x, b.max.x), std::clamp(0.0, b.min.y, b.max.y));
        EXPECT_GE(glm::length(nearest), 1.8) << str(b);
    }
}

TEST(MeshOccluders, ConcaveShapesBoxesStayOutOfTheirNotches) {
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
            const MeshOccluders occ = boxesOf(*m, si, std::string(name) + " case " + std::to_string(i));
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

TEST(MeshOccluders, NestedAndOverlappingShellsBoxesAreInsideThem) {
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
        const MeshOccluders occ = boxesOf(*m, s, name);
        expectInsideSolid(*m, occ.boxes, rng, name);
    }
}

TEST(MeshOccluders, RandomBlobsFarOffAndThinSlabsKeepTheBoxesInside) {
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

TEST(MeshOccluders, SphereBoxesAreInsideIt) {
    scenes::Rng rng(5);
    OccluderGenSettings s;
    s.maxBoxes = 6;
    const ref_ptr<Mesh> plain = uvSphere(2.0, 16, 32);
    ASSERT_TRUE(plain->closed());
    expectBoxesInsideTurned(plain, s, rng, "sphere");
}

TEST(MeshOccluders, GridSizesAndBoxCountsKeepTheBoxesInside) {
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

TEST(MeshOccluders, SameMeshSameBoxes) {
    const ref_ptr<Mesh> m = torus(3.0, 1.2, 40, 20);
    const MeshOccluders a = meshOccluders(*m), b = meshOccluders(*m);
    ASSERT_EQ(a.boxes.size(), b.boxes.size());
    for (size_t k = 0; k < a.boxes.size(); ++k) {
        EXPECT_EQ(a.boxes[k].min, b.boxes[k].min);
        EXPECT_EQ(a.boxes[k].max, b.boxes[k].max);
    }
    EXPECT_EQ(a.voxelsInside, b.voxelsInside);
}

TEST(MeshOccluders, TinyAndHugeMeshesGetTheBoxesAndPolygonsScaled) {
    // From 1e-6 to 1e6 the same shape gives the same occluders, scaled: nothing in the analysis is an absolute length.
    scenes::Rng rng(17);
    OccluderGenSettings s;
    s.maxBoxes = 8;
    s.minBoxShare = 0.005;  // as for the torus above
    const std::pair<const char*, ref_ptr<Mesh>> shapes[] = {{"notched box", notchedBox()},
                                                            {"torus", torus(3.0, 1.2, 48, 24)}};
    for (const auto& [name, plain] : shapes) {
        const MeshOccluders ref = meshOccluders(*plain, s);
        const double size = glm::length(plain->box().max - plain->box().min);
        ASSERT_FALSE(ref.boxes.empty()) << name;
        for (double scale : {1e-6, 1e-3, 1e3, 1e6}) {
            const std::string what = std::string(name) + " at scale " + std::to_string(scale);
            const ref_ptr<Mesh> m = transformed(*plain, glm::scale(dmat4(1.0), dvec3(scale)));
            ASSERT_TRUE(m->closed()) << what;
            const MeshOccluders occ = boxesOf(*m, s, what);
            expectInsideSolid(*m, occ.boxes, rng, what, 15, 20);
            ASSERT_EQ(occ.boxes.size(), ref.boxes.size()) << what;
            // Boxes of equal size (the torus' four) may come in another order: each scaled box is found among them.
            for (const Box& r : ref.boxes) {
                const auto same = [&](const Box& b) {
                    const double tol = 1e-5 * size * scale;
                    return glm::all(glm::lessThanEqual(glm::abs(b.min - r.min * scale), dvec3(tol))) &&
                           glm::all(glm::lessThanEqual(glm::abs(b.max - r.max * scale), dvec3(tol)));
                };
                EXPECT_TRUE(std::any_of(occ.boxes.begin(), occ.boxes.end(), same)) << what << ": " << str(r);
            }
        }
    }
    for (double scale : {1e-6, 1e6}) {
        SCOPED_TRACE("a quad at scale " + std::to_string(scale));
        const ref_ptr<Mesh> quad = transformed(*quadMesh(), glm::scale(dmat4(1.0), dvec3(scale)));
        const MeshOccluders occ = meshOccluders(*quad, s);
        expectPolygonRules(*quad, occ, s, rng);
        ASSERT_EQ(occ.polygons.size(), 1u);
        EXPECT_NEAR(area(occ.polygons[0]), 4.0 * scale * scale, 1e-5 * scale * scale);
    }
}

TEST(MeshOccluders, OpenMeshesGetNoBoxes) {
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

TEST(MeshOccluders, AQuadGivesItself) {
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

TEST(MeshOccluders, AnOpenBoxGivesItsFaces) {
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

TEST(MeshOccluders, AnLShapedRegionGivesConvexPolygonsInsideIt) {
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

TEST(MeshOccluders, ACurvedSurfaceGivesNoLargePolygon) {
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

TEST(MeshOccluders, NonFiniteOrEmptyMeshesGiveNothing) {
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
