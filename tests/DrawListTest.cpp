#include "sg/DrawList.h"

#include <gtest/gtest.h>

using namespace sg;

TEST(DrawList, SortsByStateThenFrontToBackAndIsStable) {
    auto m1 = make<Mesh>(), m2 = make<Mesh>();
    auto mat = make<Material>();
    DrawList l;
    const float depths[] = {5, 1, 3, 1, 0.5f, 100, -2};
    for (int k = 0; k < 7; ++k) {
        DrawItem it;
        it.mesh = k % 2 ? m1.get() : m2.get();
        it.material = mat.get();
        it.depth = depths[k];
        it.seq = uint32_t(k);
        l.add(it);
    }
    l.sort();
    ASSERT_EQ(l.order.size(), 7u);
    for (size_t k = 1; k < l.order.size(); ++k) {
        const DrawItem& a = l.items[l.order[k - 1]];
        const DrawItem& b = l.items[l.order[k]];
        if (a.mesh == b.mesh) {
            EXPECT_LE(std::max(a.depth, 0.0f), std::max(b.depth, 0.0f));
            if (a.depth == b.depth) EXPECT_LT(a.seq, b.seq);  // stable
        }
    }
    // Same-mesh items are contiguous (runs for instancing).
    int changes = 0;
    for (size_t k = 1; k < l.order.size(); ++k) changes += l.items[l.order[k - 1]].mesh != l.items[l.order[k]].mesh;
    EXPECT_EQ(changes, 1);
    // Sorting again gives the same order.
    const auto first = l.order;
    l.sort();
    EXPECT_EQ(l.order, first);
}
