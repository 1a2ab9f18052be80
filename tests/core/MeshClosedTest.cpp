// Mesh::closed(): which meshes bound solids, wound counter-clockwise seen from outside (what lets the renderer skip
// their back faces). Positions are welded where equal, so a box whose faces have corners of their own is closed.
#include "sg/core/Mesh.h"

#include <gtest/gtest.h>

#include <limits>

using namespace sg;

namespace {

std::vector<uint32_t> indicesOf(const Mesh& m) {
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < m.indexCount(); ++i) idx.push_back(m.index(i));
    return idx;
}

ref_ptr<Mesh> remade(std::vector<vec3> pos, std::vector<uint32_t> idx) {
    auto out = make<Mesh>();
    out->set(std::move(pos), {}, std::move(idx));
    return out;
}

// A tetrahedron, counter-clockwise seen from outside.
ref_ptr<Mesh> tetrahedron(const vec3& at = vec3(0.0f)) {
    auto m = make<Mesh>();
    m->set({at + vec3(0, 0, 0), at + vec3(1, 0, 0), at + vec3(0, 1, 0), at + vec3(0, 0, 1)}, {},
           {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
    return m;
}

}  // namespace

TEST(MeshClosed, ABoxWithCornersOfItsOwnPerFaceIsClosed) {
    EXPECT_TRUE(makeBoxMesh(dvec3(-1), dvec3(1), 1)->closed());
    EXPECT_TRUE(makeBoxMesh(dvec3(-6, -6, 0), dvec3(6, 6, 37), 10)->closed());  // the city's buildings
    EXPECT_TRUE(tetrahedron()->closed());
}

TEST(MeshClosed, AMeshWithAHoleIsNot) {
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1), dvec3(1), 2);
    std::vector<uint32_t> idx = indicesOf(*box);
    idx.resize(idx.size() - 3);  // one triangle gone
    EXPECT_FALSE(remade(box->positions(), idx)->closed());
}

TEST(MeshClosed, InsideOutIsNot) {
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1), dvec3(1), 1);
    std::vector<uint32_t> idx = indicesOf(*box);
    for (size_t t = 0; t < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);
    EXPECT_FALSE(remade(box->positions(), idx)->closed());
}

TEST(MeshClosed, OneFaceWoundTheOtherWayIsNot) {
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1), dvec3(1), 1);
    std::vector<uint32_t> idx = indicesOf(*box);
    std::swap(idx[1], idx[2]);
    std::swap(idx[4], idx[5]);
    EXPECT_FALSE(remade(box->positions(), idx)->closed());
}

TEST(MeshClosed, EveryPartMustEncloseVolumeFromOutside) {
    const ref_ptr<Mesh> a = tetrahedron(), b = tetrahedron(vec3(5, 0, 0));
    std::vector<vec3> pos = a->positions();
    pos.insert(pos.end(), b->positions().begin(), b->positions().end());
    std::vector<uint32_t> idx = indicesOf(*a);
    for (uint32_t i : indicesOf(*b)) idx.push_back(i + 4);
    EXPECT_TRUE(remade(pos, idx)->closed());  // two solids
    // The second turned inside out: the first's volume outweighs it, but a part that is not a solid seen from
    // outside is enough to refuse.
    std::vector<vec3> big = pos;
    for (size_t i = 0; i < 4; ++i) big[i] *= 3.0f;
    for (size_t t = 12; t < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);
    EXPECT_FALSE(remade(big, idx)->closed());
}

TEST(MeshClosed, AQuadDrawnBothWaysEnclosesNothing) {
    auto m = make<Mesh>();
    m->set({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {}, {0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2});
    EXPECT_FALSE(m->closed());  // every edge both ways, but no volume
}

TEST(MeshClosed, AnEdgeSharedByFourTrianglesIsNot) {
    // Two tetrahedra sharing an edge (not a surface around it).
    const ref_ptr<Mesh> a = tetrahedron();
    std::vector<vec3> pos = a->positions();
    pos.push_back(vec3(-1, 0, 0.5f));
    pos.push_back(vec3(0, -1, 0.5f));
    std::vector<uint32_t> idx = indicesOf(*a);
    // A second solid on the edge 0-3 (0 = origin, 3 = (0,0,1)) with corners 4 and 5.
    const uint32_t t2[] = {0, 5, 4, 0, 4, 3, 0, 3, 5, 3, 4, 5};
    idx.insert(idx.end(), std::begin(t2), std::end(t2));
    // Each solid alone is closed; together their edge 0-3 has four triangles.
    std::vector<uint32_t> alone(std::begin(t2), std::end(t2));
    for (uint32_t& i : alone) i = i == 0 ? 0 : i == 3 ? 1 : i - 2;
    ASSERT_TRUE(remade({pos[0], pos[3], pos[4], pos[5]}, alone)->closed());
    EXPECT_FALSE(remade(pos, idx)->closed());
}

TEST(MeshClosed, DegenerateAndNonFiniteMeshesAreNot) {
    auto empty = make<Mesh>();
    empty->set({}, {}, {});
    EXPECT_FALSE(empty->closed());
    const ref_ptr<Mesh> tet = tetrahedron();
    std::vector<vec3> pos = tet->positions();
    pos[3].z = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(remade(pos, indicesOf(*tet))->closed());
    // A triangle whose corners weld into one edge.
    std::vector<vec3> p2 = tet->positions();
    p2.push_back(p2[1]);
    std::vector<uint32_t> idx = indicesOf(*tet);
    idx.insert(idx.end(), {1, 4, 2});
    EXPECT_FALSE(remade(p2, idx)->closed());
}

TEST(MeshClosed, SetAgainRecomputesIt) {
    const ref_ptr<Mesh> m = tetrahedron();
    ASSERT_TRUE(m->closed());
    m->set({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, {0, 1, 2});
    EXPECT_FALSE(m->closed());
}
