#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "sg/core/Assert.h"

#include <gtest/gtest.h>

using namespace sg;

TEST(Assert, ReleaseBuildsDoNotEvaluateTheCondition) {
    int evaluated = 0;
    SG_ASSERT(++evaluated > 0, "always holds");
    EXPECT_EQ(evaluated, SG_ASSERTS_ENABLED ? 1 : 0);
}

TEST(AssertDeathTest, LodRangePastTheChildrenAborts) {
#if SG_ASSERTS_ENABLED
    auto lod = make<LOD>();
    lod->addChild(make<Geometry>(), 0.0f, 10.0f);
    lod->addChild(make<Geometry>(), 10.0f, 20.0f);
    EXPECT_EQ(lod->range(1).max, 20.0f);
    // Index 2 would read the spill storage, which a two-child LOD does not have: a null dereference.
    EXPECT_DEATH(lod->range(2),
                 "LOD\\.h:[0-9]+: assertion 'i < numChildren\\(\\)' failed: LOD::range\\(\\): child index");
#else
    GTEST_SKIP() << "asserts are compiled out (NDEBUG without SGKIT_ASSERTS)";
#endif
}
