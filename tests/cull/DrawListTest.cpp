#include "sg/cull/DrawList.h"

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
        l.add(it, depths[k]);
    }
    l.sort();
    ASSERT_EQ(l.order.size(), 7u);
    for (size_t k = 1; k < l.order.size(); ++k) {
        const uint32_t ia = l.order[k - 1], ib = l.order[k];
        if (l.items[ia].mesh == l.items[ib].mesh) {
            EXPECT_LE(std::max(depths[ia], 0.0f), std::max(depths[ib], 0.0f));
            if (depths[ia] == depths[ib]) {
                EXPECT_LT(ia, ib);  // stable
            }
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
