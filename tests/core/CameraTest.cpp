// Camera: the projected size of a length, and the setters' errors.
#include "sg/core/Camera.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

using namespace sg;

namespace {
Camera perspective(double zNear) {
    Camera cam;
    cam.setViewport(800, 600);
    cam.setPerspective(90.0, 4.0 / 3.0, zNear, 1000.0);
    return cam;
}
// The message of the std::invalid_argument `f` throws, or "" when it does not throw one.
template <class F>
std::string invalidArgument(F f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(Camera, PixelSizeHalvesWhenTheDistanceDoubles) {
    const Camera cam = perspective(0.5);
    // A 90-degree field of view over 600 pixels: a length 2 at distance 1 fills the height.
    EXPECT_NEAR(cam.pixelSize(2.0, 1.0), 600.0, 1e-9);
    EXPECT_NEAR(cam.pixelSize(2.0, 10.0), 60.0, 1e-9);
    EXPECT_NEAR(cam.pixelSize(2.0, 20.0), 30.0, 1e-9);
    EXPECT_NEAR(cam.pixelSize(4.0, 20.0), 60.0, 1e-9);
}

TEST(Camera, PixelSizeIsClampedAtTheNearPlane) {
    const Camera cam = perspective(0.5);
    EXPECT_NEAR(cam.nearDistance(), 0.5, 1e-12);
    const double atNear = cam.pixelSize(1.0, 0.5);
    EXPECT_NEAR(atNear, 600.0, 1e-9);
    EXPECT_EQ(cam.pixelSize(1.0, 0.25), atNear);
    EXPECT_EQ(cam.pixelSize(1.0, 0.0), atNear);
    EXPECT_LT(cam.pixelSize(1.0, 0.75), atNear);
}

TEST(Camera, OrthographicPixelSizeIsIndependentOfDistance) {
    Camera cam;
    cam.setViewport(800, 600);
    cam.setProjection(glm::ortho(-20.0, 20.0, -15.0, 15.0, 1.0, 100.0));
    ASSERT_FALSE(cam.perspective());
    // 30 units over 600 pixels: 20 pixels a unit.
    EXPECT_NEAR(cam.pixelSize(1.0, 5.0), 20.0, 1e-9);
    EXPECT_EQ(cam.pixelSize(1.0, 0.0), cam.pixelSize(1.0, 5.0));
    EXPECT_EQ(cam.pixelSize(1.0, 500.0), cam.pixelSize(1.0, 5.0));
}

TEST(Camera, SettersNameTheFunctionAndTheValue) {
    Camera cam;
    EXPECT_EQ(invalidArgument([&] { cam.setPerspective(180.0, 1.0, 1.0, 10.0); }),
              "Camera::setPerspective(): fovy 180.000000 is not in (0, 180)");
    EXPECT_EQ(invalidArgument([&] { cam.setPerspective(60.0, 1.0, 0.0, 10.0); }),
              "Camera::setPerspective(): near 0.000000 is not positive");
    EXPECT_EQ(invalidArgument([&] { cam.setPerspective(60.0, 1.0, 2.0, 1.0); }),
              "Camera::setPerspective(): far 1.000000 is not beyond near 2.000000");
    EXPECT_EQ(invalidArgument([&] { cam.setViewport(0, 10); }), "Camera::setViewport(): viewport 0x10 has no area");
    EXPECT_EQ(invalidArgument([&] { cam.setLookAt(dvec3(1), dvec3(1), dvec3(0, 0, 1)); }),
              "Camera::setLookAt(): eye equals centre");
    EXPECT_EQ(invalidArgument([&] { cam.setLookAt(dvec3(0), dvec3(0, 0, 1), dvec3(0, 0, 1)); }),
              "Camera::setLookAt(): up is zero or parallel to the view direction");
    EXPECT_EQ(invalidArgument([&] { cam.setView(dmat4(0.0)); }).rfind("Camera::setView(): matrix is singular", 0), 0u);
    // A failed setter leaves the camera as it was.
    const Camera before = perspective(0.5);
    Camera after = before;
    EXPECT_FALSE(invalidArgument([&] { after.setPerspective(60.0, -1.0, 1.0, 10.0); }).empty());
    EXPECT_EQ(after.projection(), before.projection());
}
