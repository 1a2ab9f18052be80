// LodHistory: last frame's LOD children, kept while the image and its structure stay the same.
#include "sg/lod/LodHistory.h"

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
    EXPECT_EQ(LodHistory::child(252), 252);
    EXPECT_EQ(LodHistory::child(253), LodHistory::kMaxChild);
    EXPECT_EQ(LodHistory::child(1000), LodHistory::kMaxChild);  // never mistaken for kNone
    FlatImage img;
    img.resize(1);
    LodHistory h;
    h.track(img, 1);
    h.show(0, 254);  // what the chooser returns for children past 253
    EXPECT_EQ(h.last(0), LodHistory::kMaxChild);
    EXPECT_NE(h.last(0), LodHistory::kNone);
}

// Changes as a viewer sees them: another child, none after one, one after none; not a first sight.
TEST(LodHistory, ChangesAreWhatAViewerSeesPopAndNotAFirstSight) {
    FlatImage img;
    img.resize(2);
    LodHistory h;
    h.track(img, 1);
    EXPECT_FALSE(h.show(0, 2));  // first sight
    EXPECT_FALSE(h.show(1, LodHistory::kNone));
    EXPECT_FALSE(h.show(0, 2));
    EXPECT_TRUE(h.show(0, LodHistory::kNone));  // gone
    EXPECT_EQ(h.last(0), LodHistory::kNone);
    EXPECT_FALSE(h.show(0, LodHistory::kNone));  // still gone
    EXPECT_TRUE(h.show(0, 1));                   // back
    EXPECT_EQ(h.last(0), 1);
    EXPECT_TRUE(h.show(0, 0));  // another child
    EXPECT_TRUE(h.show(1, 0));  // seen showing nothing, now one
    // The same from a record kept outside (a prototype's LODs, by placement).
    EXPECT_FALSE(LodHistory::changes(LodHistory::kUnseen, 3));
    EXPECT_FALSE(LodHistory::changes(LodHistory::next(LodHistory::kNone), LodHistory::kNone));
    EXPECT_TRUE(LodHistory::changes(LodHistory::next(LodHistory::kNone), 0));
    EXPECT_TRUE(LodHistory::changes(LodHistory::next(0), LodHistory::kNone));
    EXPECT_FALSE(LodHistory::changes(LodHistory::next(254), 253));  // both recorded as kMaxChild
    EXPECT_EQ(LodHistory::shown(LodHistory::next(LodHistory::kNone)), LodHistory::kNone);
}
