// The draw-cost model: it learns a machine's cost per triangle, item and pixel from measured frames,
// follows the machine when its speed changes, stays finite on repetitive frames, refuses bad input.
#include "sg/lod/DrawCostModel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace sg;

namespace {
struct Machine {
    double fixed = 2.0, perTri = 25.0e-5, perItem = 0.5e-3, perPixel = 3.0e-6, speed = 1.0;
    double ms(const DrawCostModel::Work& w) const {
        return speed * (fixed + perTri * w.triangles + perItem * w.items + perPixel * w.pixels);
    }
};
DrawCostModel::Work randomWork(std::mt19937_64& g) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return {2e4 + 3e5 * u(g), 100 + 4000 * u(g), 2e5 + 9e5 * u(g)};
}
double worstRelativeError(const DrawCostModel& m, const Machine& truth, std::mt19937_64& g) {
    double worst = 0.0;
    for (int k = 0; k < 200; ++k) {
        const auto w = randomWork(g);
        worst = std::max(worst, std::abs(m.predict(w) - truth.ms(w)) / truth.ms(w));
    }
    return worst;
}
// Predicted over measured time, summed over many frames: how far off the model is on the whole.
double overallRatio(const DrawCostModel& m, const Machine& truth, std::mt19937_64& g) {
    double predicted = 0.0, measured = 0.0;
    for (int k = 0; k < 200; ++k) {
        const auto w = randomWork(g);
        predicted += m.predict(w);
        measured += truth.ms(w);
    }
    return predicted / measured;
}
}  // namespace

TEST(DrawCostModel, LearnsTheMachineFromNoisyFrames) {
    std::mt19937_64 g(5);
    std::normal_distribution<double> noise(0.0, 0.02);
    Machine truth;
    DrawCostModel m;
    const double before = worstRelativeError(m, truth, g);
    for (int f = 0; f < 300; ++f) {
        const auto w = randomWork(g);
        m.update(w, truth.ms(w) * (1.0 + noise(g)));
    }
    EXPECT_GT(before, 0.2);  // the prior alone is not this machine
    EXPECT_LT(worstRelativeError(m, truth, g), 0.05);
    // One object's cost: its own work, without the frame's fixed part.
    const DrawCostModel::Work one{1200, 1, 5000};
    EXPECT_NEAR(m.marginal(one), truth.ms(one) - truth.fixed, 0.1);
    // The same from the rates, as the LOD budget prices its options.
    const DrawCostModel::Rates r = m.rates();
    EXPECT_NEAR(r.perTriangle * one.triangles + r.perItem * one.items + r.perPixel * one.pixels, m.marginal(one), 1e-9);
    EXPECT_EQ(m.samples(), 300u);
}

TEST(DrawCostModel, FollowsTheMachineWhenItsSpeedChanges) {
    std::mt19937_64 g(6);
    Machine truth;
    DrawCostModel forgetting(0.95), remembering(1.0);
    for (int f = 0; f < 300; ++f) {
        const auto w = randomWork(g);
        forgetting.update(w, truth.ms(w));
        remembering.update(w, truth.ms(w));
    }
    truth.speed = 1.3;  // the virtual CPU slows down
    for (int f = 0; f < 100; ++f) {
        const auto w = randomWork(g);
        forgetting.update(w, truth.ms(w));
        remembering.update(w, truth.ms(w));
    }
    EXPECT_LT(worstRelativeError(forgetting, truth, g), 0.03);
    EXPECT_GT(worstRelativeError(remembering, truth, g), 0.05);  // the factor is what makes it follow
}

// A machine whose frames take the same time whatever they draw (bound by something else, here): the fit
// finds triangles free, or less; the budget must still see a triangle's price, or it buys every finest level.
TEST(DrawCostModel, ATriangleIsNeverFree) {
    std::mt19937_64 g(9);
    std::normal_distribution<double> noise(0.0, 0.05);
    DrawCostModel m;
    double tris = 0.0, ms = 0.0;
    for (int f = 0; f < 300; ++f) {
        const auto w = randomWork(g);
        const double t = 30.0 * (1.0 + noise(g));
        m.update(w, t);
        if (f >= 280) {
            tris += w.triangles;
            ms += t;
        }
    }
    const DrawCostModel::Rates r = m.rates();
    EXPECT_GE(r.perTriangle, 0.2 * ms / tris);  // a quarter of the recent mean, give or take its smoothing
    EXPECT_GE(r.perItem, 0.0);
    EXPECT_GE(r.perPixel, 0.0);
    const DrawCostModel::Work one{1200, 1, 5000};
    EXPECT_GT(m.marginal(one), 0.0);
    EXPECT_NEAR(r.perTriangle * one.triangles + r.perItem * one.items + r.perPixel * one.pixels, m.marginal(one),
                1e-12);
}

TEST(DrawCostModel, RepetitiveFramesStayFinite) {
    // The same frame over and over excites one direction only: the fit must not wind up.
    DrawCostModel m(0.9);
    const DrawCostModel::Work w{1e5, 1000, 5e5};
    for (int f = 0; f < 10000; ++f) m.update(w, 40.0);
    EXPECT_NEAR(m.predict(w), 40.0, 0.01);
    for (double t : {0.0, 1e3, 1e6, 1e7}) {
        const double p = m.predict({t, t / 100, t * 5});
        EXPECT_TRUE(std::isfinite(p) && p >= 0.0) << p;
    }
    EXPECT_TRUE(std::isfinite(m.lastError()));
}

TEST(DrawCostModel, BadInputIsRefused) {
    EXPECT_THROW(DrawCostModel(0.0), std::invalid_argument);
    EXPECT_THROW(DrawCostModel(1.5), std::invalid_argument);
    EXPECT_THROW(DrawCostModel(std::nan("")), std::invalid_argument);
    DrawCostModel m;
    EXPECT_THROW(m.update({-1, 0, 0}, 1.0), std::invalid_argument);
    EXPECT_THROW(m.update({1, 0, 0}, std::nan("")), std::invalid_argument);
    EXPECT_THROW(m.update({1, 0, std::numeric_limits<double>::infinity()}, 1.0), std::invalid_argument);
    EXPECT_EQ(m.samples(), 0u);
    EXPECT_GT(m.predict({1e5, 0, 0}), 0.0);  // the prior
}

// A background load doubles every frame's time, then ends: with the measured time set against what each
// frame was planned to take, the predictions are back within 10% of the machine overall a dozen frames
// after either change (the fit's split into parts is still off then); the fit alone is not.
TEST(DrawCostModel, CorrectionFollowsABackgroundLoadAndItsEnd) {
    std::mt19937_64 g(7);
    Machine truth;
    DrawCostModel corrected, fitOnly;
    for (int f = 0; f < 300; ++f) {
        const auto w = randomWork(g);
        corrected.update(w, truth.ms(w));
        fitOnly.update(w, truth.ms(w));
    }
    auto frames = [&](int count) {
        for (int f = 0; f < count; ++f) {
            const auto w = randomWork(g);
            const double planned = corrected.predict(w), ms = truth.ms(w);
            corrected.update(w, ms);
            corrected.correct(planned, ms);
            fitOnly.update(w, ms);
        }
    };
    constexpr int kFrames = 12;
    truth.speed = 2.0;
    frames(kFrames);
    EXPECT_NEAR(overallRatio(corrected, truth, g), 1.0, 0.1);
    EXPECT_LT(overallRatio(fitOnly, truth, g), 0.8);
    EXPECT_GT(corrected.correction(), 1.2);
    frames(100);  // the fit learns the load too
    truth.speed = 1.0;
    frames(kFrames);
    EXPECT_NEAR(overallRatio(corrected, truth, g), 1.0, 0.1);
    EXPECT_GT(overallRatio(fitOnly, truth, g), 1.2);
    EXPECT_LT(corrected.correction(), 0.8);
}

TEST(DrawCostModel, CorrectionRefusesBadTimes) {
    DrawCostModel m;
    EXPECT_THROW(m.correct(-1.0, 1.0), std::invalid_argument);
    EXPECT_THROW(m.correct(1.0, std::nan("")), std::invalid_argument);
    EXPECT_EQ(m.correction(), 1.0);
    m.correct(0.0, 5.0);  // nothing was predicted: counted as the largest step, not a division by 0
    EXPECT_NEAR(m.correction(), std::pow(4.0, 0.25), 1e-12);
}

// The work a mesh adds to a frame, in triangles: a point or a segment as the quad the rasterizer draws for it.
TEST(DrawCostModel, PointsAndLinesCountAsQuads) {
    auto tri = makeBoxMesh(dvec3(0.0), dvec3(1.0));
    EXPECT_EQ(triangleWork(*tri), double(tri->triangleCount()));
    auto pts = make<Mesh>();
    pts->setPoints({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
    EXPECT_EQ(triangleWork(*pts), 3.0 * kQuadTriangles);
    auto lines = make<Mesh>();
    lines->setLines({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {0, 1, 1, 2});
    EXPECT_EQ(triangleWork(*lines), 2.0 * kQuadTriangles);
}
