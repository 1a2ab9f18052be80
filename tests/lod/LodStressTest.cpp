// The stress filter: it brings an overloaded frame back into its budget band and settles there, lets go
// when the load drops, and refuses bad parameters by name.
#include "sg/lod/LodStress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

using namespace sg;

namespace {
// A scene whose far detail dominates: full detail costs 5 + 95 ms; scaling the LOD distances by s leaves
// about 1/s^2 of the detailed area.
double frameAt(double scale) { return 5.0 + 95.0 / (scale * scale); }
}  // namespace

TEST(LodStress, BringsAnOverloadedFrameIntoTheBandAndSettles) {
    LodStress st;  // 33.3 ms budget, band [0.8, 0.95]
    double ms = frameAt(1.0);
    EXPECT_GT(ms, 3.0 * st.params().budgetMs);
    double lastScale = 1.0;
    int settledAt = -1;
    for (int f = 0; f < 60; ++f) {
        const double s = st.update(ms);
        ms = frameAt(s);
        const double load = ms / st.params().budgetMs;
        const bool inBand = load >= st.params().low * 0.97 && load <= st.params().high * 1.03;
        if (inBand && settledAt < 0) settledAt = f;
        if (settledAt >= 0 && f > settledAt) {
            EXPECT_TRUE(inBand) << "frame " << f << " load " << load;
            EXPECT_LT(std::abs(s / lastScale - 1.0), 0.05) << "frame " << f;  // no swinging once there
        }
        lastScale = s;
    }
    EXPECT_GE(settledAt, 0);
    EXPECT_LE(settledAt, 10);
    EXPECT_GT(st.scale(), 1.5);
}

TEST(LodStress, LightLoadKeepsFullDetailAndALoadSpikeIsUndone) {
    LodStress st;
    for (int f = 0; f < 10; ++f) EXPECT_EQ(st.update(10.0), 1.0);
    for (int f = 0; f < 5; ++f) st.update(80.0);
    EXPECT_GT(st.scale(), 2.0);
    for (int f = 0; f < 60; ++f) st.update(10.0);
    EXPECT_EQ(st.scale(), 1.0);
    LodStress::Params p;
    p.maxScale = 3.0;
    LodStress capped(p);
    for (int f = 0; f < 20; ++f) capped.update(1000.0);
    EXPECT_EQ(capped.scale(), 3.0);
}

TEST(LodStress, BadInputIsRefusedByName) {
    auto expectThrow = [](LodStress::Params p, const char* name) {
        try {
            LodStress s(p);
            ADD_FAILURE() << name << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    };
    LodStress::Params p;
    p.budgetMs = 0;
    expectThrow(p, "budgetMs");
    p = {};
    p.low = std::nan("");
    expectThrow(p, "low");
    p = {};
    p.high = 0.5;
    expectThrow(p, "high");
    p = {};
    p.gain = -1;
    expectThrow(p, "gain");
    p = {};
    p.maxScale = 0.5;
    expectThrow(p, "maxScale");
    LodStress s;
    EXPECT_THROW(s.update(-1.0), std::invalid_argument);
    EXPECT_THROW(s.update(std::nan("")), std::invalid_argument);
    EXPECT_EQ(s.scale(), 1.0);
}
