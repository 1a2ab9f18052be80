// MeshFeatures: a vertex's, an instance's and a texel's feature id from each source, the null id, and the nearest
// texel with REPEAT wrapping (rows top first: v = 0 is row 0).
#include "sg/core/Features.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

FeatureIdSet idsSet(FeatureIdSet::Source source, std::vector<uint32_t> ids) {
    FeatureIdSet s;
    s.source = source;
    s.ids = std::move(ids);
    return s;
}

// A 2 x 2 texture whose texel (x, y) has R = 10 * y + x, G = 100 + R, B = 0, A = 255.
ref_ptr<Texture> quad() {
    std::vector<uint8_t> rgba;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
            const uint8_t r = uint8_t(10 * y + x);
            rgba.insert(rgba.end(), {r, uint8_t(100 + r), 0, 255});
        }
    return make<Texture>(2, 2, std::move(rgba));
}

TEST(Features, AttributeAndInstanceIds) {
    auto f = make<MeshFeatures>();
    f->sets.push_back(idsSet(FeatureIdSet::Source::Attribute, {4, 7, 9}));
    f->sets.push_back(idsSet(FeatureIdSet::Source::Instance, {2, 3}));
    EXPECT_EQ(f->idAt(0, 0), 4);
    EXPECT_EQ(f->idAt(0, 2), 9);
    EXPECT_EQ(f->idAt(0, 3), -1);  // past the ids
    EXPECT_EQ(f->idAt(1, 1), 3);
    EXPECT_EQ(f->idAt(2, 0), -1);  // no such set
}

TEST(Features, ImplicitIdsAreTheIndex) {
    auto f = make<MeshFeatures>();
    FeatureIdSet s = idsSet(FeatureIdSet::Source::Implicit, {});
    s.featureCount = 5;
    f->sets.push_back(s);
    EXPECT_EQ(f->idAt(0, 0), 0);
    EXPECT_EQ(f->idAt(0, 4), 4);
    EXPECT_EQ(f->idAt(0, 5), -1);
}

TEST(Features, NullFeatureIdIsNoFeature) {
    auto f = make<MeshFeatures>();
    FeatureIdSet s = idsSet(FeatureIdSet::Source::Attribute, {1, 65535, 2});
    s.hasNullFeatureId = true;
    s.nullFeatureId = 65535;
    f->sets.push_back(s);
    EXPECT_EQ(f->idAt(0, 0), 1);
    EXPECT_EQ(f->idAt(0, 1), -1);
    EXPECT_EQ(f->idAt(0, 2), 2);
}

TEST(Features, TextureIdsCombineChannelsLittleEndian) {
    auto f = make<MeshFeatures>();
    FeatureIdSet s = idsSet(FeatureIdSet::Source::Texture, {});
    s.texture = quad();
    s.channels = {0, 1};  // R the low byte, G the high one
    f->sets.push_back(s);
    // Texel (1, 1): R = 11, G = 111.
    EXPECT_EQ(f->idAtUv(0, vec2(0.75f, 0.75f)), 11 + 111 * 256);
    EXPECT_EQ(f->idAt(0, 0), -1);  // a texture set asked by index
}

TEST(Features, TexelsAtEdgesAndWrapped) {
    auto t = quad();
    auto r = [&](float u, float v) { return int(texelChannels(*t, vec2(u, v), {0})[0]); };
    EXPECT_EQ(r(0.0f, 0.0f), 0);  // v = 0 is the top row, row 0
    EXPECT_EQ(r(0.49f, 0.0f), 0);
    EXPECT_EQ(r(0.5f, 0.0f), 1);
    EXPECT_EQ(r(0.0f, 0.5f), 10);
    EXPECT_EQ(r(0.99f, 0.99f), 11);
    EXPECT_EQ(r(1.0f, 0.0f), 0);  // REPEAT: u = 1 is u = 0
    EXPECT_EQ(r(1.75f, 0.25f), 1);
    EXPECT_EQ(r(-0.25f, 0.0f), 1);   // fract(-0.25) = 0.75
    EXPECT_EQ(r(0.25f, -0.75f), 0);  // fract(-0.75) = 0.25
    const auto all = texelChannels(*t, vec2(0.75f, 0.75f), {3, 2, 1, 0});
    EXPECT_EQ(all, (std::vector<uint8_t>{255, 0, 111, 11}));
}

}  // namespace
