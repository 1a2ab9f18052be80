// sg::CameraMotion: a camera's speed and turn estimated from its frames, and the camera carried ahead by them.
#include "sg/paging/CameraMotion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace {

using namespace sg;

// A camera at `eye`, looking horizontally at `yaw` radians from +y toward +x, +z up.
Camera heading(const dvec3& eye, double yaw) {
    Camera c;
    c.setViewport(320, 240);
    c.setPerspective(60.0, 4.0 / 3.0, 1.0, 1000.0);
    c.setLookAt(eye, eye + dvec3(std::sin(yaw), std::cos(yaw), 0.0), dvec3(0, 0, 1));
    return c;
}

// Flying along x at 10 m/s while turning at 0.3 rad/s, frames at uneven intervals (as a machine's frames come):
// a second ahead of t = 1 is where the path is at t = 2, position and view direction, however uneven the frames.
TEST(CameraMotion, ACameraMovingAndTurningSteadilyIsCarriedAheadAlongItsPath) {
    auto at = [](double t) { return heading(dvec3(10.0 * t, 0.0, 5.0), 0.3 * t); };
    CameraMotion motion;
    double t = 0.0;
    for (int k = 0; t < 1.0; ++k) {
        motion.observe(at(t), t);
        if (t + 0.045 >= 1.0) break;  // t: the last frame observed
        t += k % 2 ? 0.045 : 0.02;
    }
    const std::optional<Camera> ahead = motion.predict(at(t), 1.0);
    ASSERT_TRUE(ahead);
    const Camera want = at(t + 1.0);
    EXPECT_NEAR(glm::length(ahead->eye() - want.eye()), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(ahead->viewDirection() - want.viewDirection()), 0.0, 1e-9);
    EXPECT_NEAR(motion.velocity().x, 10.0, 1e-9);
    EXPECT_NEAR(glm::length(motion.turn()), 0.3, 1e-9);
    // The projection and viewport are the camera's.
    EXPECT_EQ(ahead->projection(), want.projection());
    EXPECT_EQ(ahead->width(), 320);
}

TEST(CameraMotion, NothingIsPredictedAtRestBeforeTwoFramesOrAfterAPause) {
    CameraMotion motion;
    const Camera a = heading(dvec3(0, 0, 5), 0.0), b = heading(dvec3(1, 0, 5), 0.0);
    EXPECT_FALSE(motion.predict(a, 1.0));
    motion.observe(a, 0.0);
    EXPECT_FALSE(motion.predict(a, 1.0));  // one frame: no motion known
    motion.observe(b, 0.1);
    EXPECT_TRUE(motion.predict(b, 1.0));
    EXPECT_FALSE(motion.predict(b, 0.0));
    EXPECT_FALSE(motion.predict(b, -1.0));
    EXPECT_FALSE(motion.predict(b, std::numeric_limits<double>::quiet_NaN()));
    motion.observe(b, 5.0);  // after a pause longer than kMaxGapSeconds: starts over
    EXPECT_FALSE(motion.predict(b, 1.0));
    motion.observe(b, 5.1);  // two frames at the same place: at rest
    EXPECT_FALSE(motion.predict(b, 1.0));
    motion.observe(a, 5.2);
    motion.reset();
    EXPECT_FALSE(motion.predict(a, 1.0));
}

// A spin of 10 rad/s carried a second ahead would turn the view round and round: it turns a quarter at most.
TEST(CameraMotion, AFastSpinIsCarriedAheadAtMostAQuarterTurn) {
    CameraMotion motion;
    for (int k = 0; k <= 10; ++k) motion.observe(heading(dvec3(0, 0, 5), 0.01 * k * 10.0 / 1.0), 0.01 * k);
    const Camera now = heading(dvec3(0, 0, 5), 1.0);
    const std::optional<Camera> ahead = motion.predict(now, 1.0);
    ASSERT_TRUE(ahead);
    const double turned = std::acos(std::clamp(glm::dot(ahead->viewDirection(), now.viewDirection()), -1.0, 1.0));
    EXPECT_NEAR(turned, CameraMotion::kMaxTurn, 1e-6);
    EXPECT_NEAR(glm::length(ahead->eye() - now.eye()), 0.0, 1e-9);
}

TEST(CameraMotion, BadTimesAreIgnoredAndAnUnboundedMotionPredictsNothing) {
    CameraMotion motion;
    motion.observe(heading(dvec3(0, 0, 5), 0.0), 0.0);
    motion.observe(heading(dvec3(1, 0, 5), 0.0), std::numeric_limits<double>::quiet_NaN());
    motion.observe(heading(dvec3(1, 0, 5), 0.0), -1.0);  // earlier than the last frame
    motion.observe(heading(dvec3(1, 0, 5), 0.0), std::numeric_limits<double>::infinity());
    motion.observe(heading(dvec3(1, 0, 5), 0.0), 0.5);
    EXPECT_NEAR(motion.velocity().x, 2.0, 1e-12);  // only the last, good frame counted
    // A jump of 1e300 m in a millisecond: no finite camera ahead, and no exception.
    CameraMotion wild;
    wild.observe(heading(dvec3(0, 0, 5), 0.0), 0.0);
    wild.observe(heading(dvec3(1e300, 0, 5), 0.0), 1e-3);
    const Camera now = heading(dvec3(1e300, 0, 5), 0.0);
    EXPECT_NO_THROW({
        const std::optional<Camera> ahead = wild.predict(now, 1e10);
        EXPECT_FALSE(ahead);
    });
}

}  // namespace
