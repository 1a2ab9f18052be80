// ObbTree: boxes that hold their triangles, tight for a rotated mesh, leaves of at most 10 triangles; the cache.
#include "sg/cull/ObbTree.h"

#include <gtest/gtest.h>

#include <functional>

using namespace sg;

namespace {
// A bar 20 x 1 x 1 (gridded), turned 30 degrees about z in the mesh's own coordinates.
ref_ptr<Mesh> turnedBar() {
    ref_ptr<Mesh> box = makeBoxMesh(dvec3(-10, -0.5, -0.5), dvec3(10, 0.5, 0.5), 8);
    const dmat4 r = glm::rotate(dmat4(1.0), glm::radians(30.0), dvec3(0, 0, 1));
    std::vector<vec3> pos;
    for (const vec3& p : box->positions()) pos.push_back(vec3(r * dvec4(dvec3(p), 1.0)));
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < box->indexCount(); ++i) idx.push_back(box->index(i));
    auto m = make<Mesh>();
    m->set(pos, box->normals(), idx);
    return m;
}

bool inside(const ObbTree::Node& n, const dvec3& p) {
    const dvec3 d = p - n.centre;
    for (int a = 0; a < 3; ++a)
        if (std::abs(glm::dot(d, n.axis[a])) > n.half[a]) return false;
    return true;
}
}  // namespace

TEST(ObbTree, RootIsTightForATurnedBarAndEveryNodeHoldsItsTriangles) {
    const ref_ptr<Mesh> mesh = turnedBar();
    const ObbTree tree(*mesh);
    ASSERT_FALSE(tree.empty());
    const ObbTree::Node& root = tree.root();
    // Its volume is the bar's (20 x 1 x 1, within 1%), not the 193 of its axis-aligned box (17.8 x 10.9 x 1).
    EXPECT_NEAR(8.0 * root.half.x * root.half.y * root.half.z, 20.0, 0.2);
    EXPECT_EQ(root.triangles, mesh->triangleCount());
    // Every vertex lies in the root; each inner node's children split its triangles; leaves hold <= 10.
    for (const vec3& p : mesh->positions()) EXPECT_TRUE(inside(root, dvec3(p)));
    uint64_t leafTriangles = 0;
    std::function<void(uint32_t)> walk = [&](uint32_t i) {
        const ObbTree::Node& n = tree.node(i);
        if (n.first == 0) {
            EXPECT_LE(n.triangles, ObbTree::kLeafTriangles);
            leafTriangles += n.triangles;
            return;
        }
        EXPECT_EQ(tree.node(n.first).triangles + tree.node(n.first + 1).triangles, n.triangles);
        walk(n.first);
        walk(n.first + 1);
    };
    walk(0);
    EXPECT_EQ(leafTriangles, mesh->triangleCount());
    EXPECT_GE(tree.depth(), 4);
}

TEST(ObbTree, LeavesHoldTheirTrianglesVertices) {
    // Vertices of the triangles in each leaf, found by brute force: each lies in some leaf's box.
    const ref_ptr<Mesh> mesh = turnedBar();
    const ObbTree tree(*mesh);
    std::vector<uint32_t> leaves;
    for (uint32_t i = 0; i < tree.nodeCount(); ++i)
        if (tree.node(i).first == 0) leaves.push_back(i);
    for (uint32_t t = 0; t < mesh->triangleCount(); ++t) {
        bool held = false;
        for (uint32_t l : leaves) {
            bool all = true;
            for (int k = 0; k < 3; ++k)
                all = all && inside(tree.node(l), dvec3(mesh->positions()[mesh->index(3 * t + k)]));
            held = held || all;
        }
        EXPECT_TRUE(held) << "triangle " << t;
    }
}

TEST(ObbTree, NonFiniteMeshGivesAnEmptyTreeAndTheCacheFollowsTheMesh) {
    auto bad = make<Mesh>();
    bad->set({vec3(0), vec3(1, 0, 0), vec3(0, std::nanf(""), 0)}, {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)},
             {0, 1, 2});
    EXPECT_TRUE(ObbTree(*bad).empty());

    ObbTree::Cache cache;
    ref_ptr<Mesh> mesh = turnedBar();
    const ObbTree* first = &cache.get(*mesh);
    EXPECT_EQ(&cache.get(*mesh), first);
    EXPECT_EQ(cache.size(), 1u);
    // Set again: rebuilt for the new triangles.
    mesh->set({vec3(0), vec3(1, 0, 0), vec3(0, 1, 0)}, {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)}, {0, 1, 2});
    EXPECT_EQ(cache.get(*mesh).root().triangles, 1u);
    // Not asked for over 8 frames: dropped.
    for (int f = 0; f < 16; ++f) cache.nextFrame(8);
    EXPECT_EQ(cache.size(), 0u);
}
