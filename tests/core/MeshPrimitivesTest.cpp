// Mesh holding points and lines: what set*() check, what the counts say, and what a triangle mesh's outline takes.
#include "sg/core/Mesh.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

using namespace sg;

TEST(MeshPrimitives, PointsHaveNoIndicesAndCountEachPosition) {
    auto m = make<Mesh>();
    m->setPoints({{0, 0, 0}, {1, 2, 3}, {-1, 0, 5}}, {vec4(1, 0, 0, 1), vec4(0, 1, 0, 1), vec4(0, 0, 1, 1)});
    EXPECT_EQ(m->primitive(), Primitive::Points);
    EXPECT_EQ(m->indexCount(), 0u);
    EXPECT_EQ(m->pointCount(), 3u);
    EXPECT_EQ(m->triangleCount(), 0u);
    EXPECT_EQ(m->lineCount(), 0u);
    EXPECT_EQ(m->primitiveCount(), 3u);
    EXPECT_EQ(m->box().min, dvec3(-1, 0, 0));
    EXPECT_EQ(m->box().max, dvec3(1, 2, 5));
    EXPECT_FALSE(m->closed());
}

TEST(MeshPrimitives, LinesTakeIndexPairs) {
    auto m = make<Mesh>();
    m->setLines({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {0, 1, 1, 2});
    EXPECT_EQ(m->primitive(), Primitive::Lines);
    EXPECT_EQ(m->lineCount(), 2u);
    EXPECT_EQ(m->triangleCount(), 0u);  // four indices are not a triangle and a third
    EXPECT_EQ(m->primitiveCount(), 2u);
    EXPECT_THROW(m->setLines({{0, 0, 0}, {1, 0, 0}}, {0, 1, 1}), std::invalid_argument);
    EXPECT_THROW(m->setLines({{0, 0, 0}, {1, 0, 0}}, {0, 2}), std::invalid_argument);
}

TEST(MeshPrimitives, SetBackToTrianglesForgetsThePrimitive) {
    auto m = make<Mesh>();
    m->setPoints({{0, 0, 0}});
    m->set({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, {0, 1, 2});
    EXPECT_EQ(m->primitive(), Primitive::Triangles);
    EXPECT_EQ(m->triangleCount(), 1u);
    EXPECT_EQ(m->pointCount(), 0u);
}

TEST(MeshPrimitives, SizesOfAttributesAreChecked) {
    auto m = make<Mesh>();
    EXPECT_THROW(m->setPoints({{0, 0, 0}, {1, 0, 0}}, {vec4(1)}), std::invalid_argument);
    EXPECT_THROW(m->setPoints({{0, 0, 0}}, {}, {vec3(0, 0, 1), vec3(0, 0, 1)}), std::invalid_argument);
    m->setPoints({{0, 0, 0}, {1, 0, 0}});
    EXPECT_THROW(m->setIntensities({1}), std::invalid_argument);
    m->setIntensities({7, 65535});
    EXPECT_EQ(m->intensities()[1], 65535u);
    EXPECT_EQ(m->bytes(), 2 * sizeof(vec3) + 2 * sizeof(uint16_t));
    m->setPoints({{0, 0, 0}});  // clears them
    EXPECT_TRUE(m->intensities().empty());
}

TEST(MeshPrimitives, NonFinitePointsAreKeptWithAnInvalidBound) {
    auto m = make<Mesh>();
    m->setPoints({{0, 0, 0}, {std::numeric_limits<float>::quiet_NaN(), 0, 0}});
    EXPECT_EQ(m->pointCount(), 2u);
    EXPECT_FALSE(m->validBound());
}

TEST(MeshPrimitives, PointSpacingIsPositiveAndFiniteOrZero) {
    auto m = make<Mesh>();
    m->setPointSpacing(0.25f);
    m->setPoints({{0, 0, 0}});
    EXPECT_FLOAT_EQ(m->pointSpacing(), 0.25f);  // kept by set*()
    m->setPointSpacing(-1.0f);
    EXPECT_EQ(m->pointSpacing(), 0.0f);
    m->setPointSpacing(std::numeric_limits<float>::infinity());
    EXPECT_EQ(m->pointSpacing(), 0.0f);
}

TEST(MeshPrimitives, OutlineBelongsToTriangles) {
    auto m = make<Mesh>();
    m->set({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, {0, 1, 2});
    m->setOutline({0, 1, 1, 2, 2, 0});
    EXPECT_EQ(m->outline().size(), 6u);
    EXPECT_THROW(m->setOutline({0, 1, 2}), std::invalid_argument);
    EXPECT_THROW(m->setOutline({0, 3}), std::invalid_argument);
    m->set({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, {0, 1, 2});
    EXPECT_TRUE(m->outline().empty());  // set() clears it
    m->setPoints({{0, 0, 0}, {1, 0, 0}});
    EXPECT_THROW(m->setOutline({0, 1}), std::invalid_argument);
}
