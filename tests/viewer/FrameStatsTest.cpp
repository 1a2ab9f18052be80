// FrameHistory: the last frames' stage times kept in order, their means, the frame rate and percentiles.
#include "sg/viewer/FrameStats.h"

#include <gtest/gtest.h>

namespace {

using namespace sg;

StageTimes frameOf(uint64_t n, double ms) {
    StageTimes t;
    t.frame = n;
    t.cullMs = ms / 4.0;
    t.drawMs = ms / 2.0;
    t.frameMs = t.intervalMs = ms;
    return t;
}

TEST(FrameHistory, KeepsTheLastFramesOldestFirst) {
    FrameHistory h(3);
    EXPECT_EQ(h.last().frame, 0u);  // none yet: a zero frame
    EXPECT_EQ(h.rate(), 0.0);
    for (uint64_t n = 0; n < 5; ++n) h.push(frameOf(n, 10.0 * double(n + 1)));
    ASSERT_EQ(h.size(), 3u);
    EXPECT_EQ(h.at(0).frame, 2u);
    EXPECT_EQ(h.at(2).frame, 4u);
    EXPECT_EQ(h.last().frame, 4u);
    const StageTimes m = h.mean();  // frames of 30, 40 and 50 ms
    EXPECT_DOUBLE_EQ(m.frameMs, 40.0);
    EXPECT_DOUBLE_EQ(m.drawMs, 20.0);
    EXPECT_DOUBLE_EQ(m.cullMs, 10.0);
    EXPECT_EQ(m.frame, 4u);
    EXPECT_DOUBLE_EQ(h.rate(), 25.0);  // 3 frames in 120 ms
    EXPECT_DOUBLE_EQ(h.percentile(&StageTimes::frameMs, 0.0), 30.0);
    EXPECT_DOUBLE_EQ(h.percentile(&StageTimes::frameMs, 50.0), 40.0);
    EXPECT_DOUBLE_EQ(h.percentile(&StageTimes::frameMs, 100.0), 50.0);
    h.clear();
    EXPECT_EQ(h.size(), 0u);
    FrameHistory one(0);  // at least one frame is kept
    one.push(frameOf(7, 5.0));
    one.push(frameOf(8, 6.0));
    EXPECT_EQ(one.size(), 1u);
    EXPECT_EQ(one.last().frame, 8u);
}

// The GPU's time is averaged over the frames that know it (StageTimes::gpuTimed); with none, the mean does not know it.
TEST(FrameHistory, TheGpuMeanIsOfTheFramesThatKnowIt) {
    FrameHistory h(4);
    StageTimes t = frameOf(0, 10.0);
    h.push(t);
    EXPECT_FALSE(h.mean().gpuTimed);
    EXPECT_EQ(h.mean().gpuMs, 0.0);
    t.gpuTimed = true;
    t.gpuMs = 6.0;
    h.push(t);
    t.gpuMs = 2.0;
    h.push(t);
    const StageTimes m = h.mean();  // (6 + 2) / 2, the untimed frame left out
    EXPECT_TRUE(m.gpuTimed);
    EXPECT_DOUBLE_EQ(m.gpuMs, 4.0);
}

}  // namespace
