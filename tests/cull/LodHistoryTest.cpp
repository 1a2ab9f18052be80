// LodHistory: last frame's LOD children, kept while the image and its structure stay the same.
#include "sg/cull/LodHistory.h"

#include <gtest/gtest.h>

using namespace sg;

TEST(LodHistory, StartsWithNothingShown) {
    FlatImage img;
    img.resize(4);
    LodHistory h;
    h.track(img, 1);
    for (uint32_t i = 0; i < 4; ++i) EXPECT_EQ(h.last(i), LodHistory::kNone);
}

TEST(LodHistory, KeepsWhatWasShownWhileTheImageAndItsStructureStay) {
    FlatImage img;
    img.resize(4);
    LodHistory h;
    h.track(img, 7);
    h.show(1, 2);
    h.show(3, 0);
    h.track(img, 7);  // the next frame
    EXPECT_EQ(h.last(1), 2);
    EXPECT_EQ(h.last(3), 0);
    EXPECT_EQ(h.last(0), LodHistory::kNone);
}

TEST(LodHistory, ForgetsWhenTheStructureVersionChanges) {
    FlatImage img;
    img.resize(4);
    LodHistory h;
    h.track(img, 7);
    h.show(1, 2);
    h.track(img, 8);
    EXPECT_EQ(h.last(1), LodHistory::kNone);
}

TEST(LodHistory, ForgetsForAnotherImageOrAResizedOne) {
    FlatImage a, b;
    a.resize(4);
    b.resize(4);
    LodHistory h;
    h.track(a, 7);
    h.show(1, 2);
    h.track(b, 7);  // same version, another image
    EXPECT_EQ(h.last(1), LodHistory::kNone);
    h.show(1, 2);
    b.resize(6);
    h.track(b, 7);
    EXPECT_EQ(h.last(1), LodHistory::kNone);
    EXPECT_EQ(h.last(5), LodHistory::kNone);
}

TEST(LodHistory, ChildNumbersAreCappedAndNoneIsNegative) {
    EXPECT_EQ(LodHistory::child(-1), LodHistory::kNone);
    EXPECT_EQ(LodHistory::child(0), 0);
    EXPECT_EQ(LodHistory::child(253), 253);
    EXPECT_EQ(LodHistory::child(254), 254);
    EXPECT_EQ(LodHistory::child(1000), 254);  // never mistaken for kNone
}
