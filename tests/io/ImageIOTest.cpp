// Image comparison: differing pixels and the mean absolute error the LOD and walkthrough figures report.
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace sg;

namespace {
Image solid(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
    Image img{w, h, std::vector<uint8_t>(size_t(w) * size_t(h) * 4, 255)};
    for (size_t i = 0; i < img.rgba.size(); i += 4) img.rgba[i] = r, img.rgba[i + 1] = g, img.rgba[i + 2] = b;
    return img;
}
}  // namespace

TEST(ImageIO, MeanAbsoluteErrorAveragesTheRgbChannelsOfEveryPixel) {
    const Image a = solid(2, 1, 10, 20, 30);
    Image b = a;
    EXPECT_EQ(meanAbsoluteError(a, b), 0.0);
    b.rgba[0] = 40;  // one channel of one pixel off by 30
    b.rgba[3] = 0;   // alpha is not compared
    EXPECT_DOUBLE_EQ(meanAbsoluteError(a, b), 30.0 / 6.0);
    EXPECT_EQ(countDifferingPixels(a, b), 1u);
    EXPECT_EQ(countDifferingPixels(a, b, 30), 0u);
}

TEST(ImageIO, ComparingImagesOfDifferentSizesNamesTheFunction) {
    const Image a = solid(2, 1, 0, 0, 0), b = solid(1, 2, 0, 0, 0);
    try {
        meanAbsoluteError(a, b);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "meanAbsoluteError(): sizes differ (2x1 vs 1x2)");
    }
    EXPECT_THROW(countDifferingPixels(a, b), std::invalid_argument);
}
