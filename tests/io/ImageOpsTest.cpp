// bleedIntoTransparent: the colour a cut-out texture shows under its transparent texels.
#include "sg/io/ImageOps.h"

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <string>

using namespace sg;

namespace {
// w x h texels, all transparent black.
Image transparent(int w, int h) { return Image{w, h, std::vector<uint8_t>(size_t(w) * size_t(h) * 4u, 0)}; }
void set(Image& img, int x, int y, std::array<uint8_t, 4> c) {
    for (size_t k = 0; k < 4; ++k) img.rgba[(size_t(y) * size_t(img.width) + size_t(x)) * 4u + k] = c[k];
}
std::array<int, 4> at(const Image& img, int x, int y) {
    const uint8_t* p = &img.rgba[(size_t(y) * size_t(img.width) + size_t(x)) * 4u];
    return {p[0], p[1], p[2], p[3]};
}
}  // namespace

TEST(ImageOps, OneVisibleTexelColoursEveryHiddenOneAndAlphaStays) {
    Image img = transparent(5, 4);
    set(img, 2, 1, {200, 40, 60, 255});
    bleedIntoTransparent(img);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x)
            EXPECT_EQ(at(img, x, y), (std::array<int, 4>{200, 40, 60, x == 2 && y == 1 ? 255 : 0})) << x << "," << y;
}

TEST(ImageOps, EachRingAveragesTheNeighboursFilledBeforeIt) {
    // Red in one corner, blue (half opaque: any alpha but 0 is visible) in the other of a 3 x 3 image.
    Image img = transparent(3, 3);
    set(img, 0, 0, {255, 0, 0, 255});
    set(img, 2, 2, {0, 0, 255, 128});
    bleedIntoTransparent(img);
    // First ring: the neighbours of one corner take its colour.
    EXPECT_EQ(at(img, 1, 0), (std::array<int, 4>{255, 0, 0, 0}));
    EXPECT_EQ(at(img, 0, 1), (std::array<int, 4>{255, 0, 0, 0}));
    EXPECT_EQ(at(img, 2, 1), (std::array<int, 4>{0, 0, 255, 0}));
    EXPECT_EQ(at(img, 1, 2), (std::array<int, 4>{0, 0, 255, 0}));
    // Second ring: the rounded mean of the first ring's colours around it, (255 x 2 + 2) / 4 = 128.
    EXPECT_EQ(at(img, 1, 1), (std::array<int, 4>{128, 0, 128, 0}));
    EXPECT_EQ(at(img, 2, 0), (std::array<int, 4>{128, 0, 128, 0}));
    EXPECT_EQ(at(img, 0, 2), (std::array<int, 4>{128, 0, 128, 0}));
    EXPECT_EQ(at(img, 0, 0), (std::array<int, 4>{255, 0, 0, 255}));
    EXPECT_EQ(at(img, 2, 2), (std::array<int, 4>{0, 0, 255, 128}));
}

TEST(ImageOps, NothingVisibleLeavesTheImageAsItIs) {
    Image img = transparent(3, 2);
    set(img, 1, 1, {10, 20, 30, 0});  // a hidden colour of its own
    const Image before = img;
    bleedIntoTransparent(img);
    EXPECT_EQ(img.rgba, before.rgba);
}

TEST(ImageOps, APixelCountThatIsNotTheSizeThrows) {
    Image img = transparent(3, 2);
    img.rgba.pop_back();
    try {
        bleedIntoTransparent(img);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("bleedIntoTransparent(): ", 0), 0u) << e.what();
    }
}
