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
    EXPECT_EQ(LodHistory::child(124), 124);
    EXPECT_EQ(LodHistory::child(125), LodHistory::kMaxChild);
    EXPECT_EQ(LodHistory::child(1000), LodHistory::kMaxChild);  // never mistaken for kNone
    FlatImage img;
    img.resize(1);
    LodHistory h;
    h.track(img, 1);
    h.show(0, 254);  // what the chooser returns for children past 253
    EXPECT_EQ(h.last(0), LodHistory::kMaxChild);
}

// Last frame's child, and the child shown before frames that showed none; changes() as a viewer sees them.
TEST(LodHistory, RemembersTheChildShownThroughFramesThatShowedNone) {
    FlatImage img;
    img.resize(3);
    LodHistory h;
    h.track(img, 1);
    EXPECT_FALSE(h.show(0, 2));  // first sight: no change
    EXPECT_FALSE(h.show(1, LodHistory::kNone));
    EXPECT_EQ(LodHistory::drawn(h.record(2)), LodHistory::kNone);  // not seen
    EXPECT_TRUE(h.show(0, LodHistory::kNone));                     // gone
    EXPECT_EQ(h.last(0), LodHistory::kNone);
    EXPECT_EQ(LodHistory::drawn(h.record(0)), 2);
    EXPECT_FALSE(h.show(0, LodHistory::kNone));  // still gone
    EXPECT_EQ(LodHistory::drawn(h.record(0)), 2);
    EXPECT_TRUE(h.show(0, 1));  // back, at another child
    EXPECT_EQ(h.last(0), 1);
    EXPECT_EQ(LodHistory::drawn(h.record(0)), 1);
    EXPECT_FALSE(h.show(0, 1));
    // Seen, never shown: no child to remember; showing one is a change.
    EXPECT_FALSE(h.show(1, LodHistory::kNone));
    EXPECT_EQ(LodHistory::drawn(h.record(1)), LodHistory::kNone);
    EXPECT_TRUE(h.show(1, 0));
    // Every child survives a frame that showed none.
    for (int c = 0; c <= LodHistory::kMaxChild; ++c) {
        const uint8_t gone = LodHistory::next(uint8_t(c), LodHistory::kNone);
        EXPECT_EQ(LodHistory::shown(gone), LodHistory::kNone) << c;
        EXPECT_EQ(LodHistory::drawn(gone), c);
        EXPECT_NE(gone, LodHistory::kUnseen);
    }
}
