// Navigator (examples/common): the three modes keep one view, trackball orbit, zoom and pan, fly and walk
// moves, walking stopped by walls and kept above the ground, the pitch limit and the speed.
#include "common/FittedCamera.h"
#include "common/Navigator.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sg;
using namespace common;

namespace {

void expectNear(const dvec3& a, const dvec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Navigator, SwitchingModesKeepsTheView) {
    Navigator nav(Box{dvec3(-10), dvec3(10)}, dvec3(0, 0, 1));
    nav.lookAt(dvec3(30, -30, 20), dvec3(0));
    const dvec3 eye = nav.eye(), f = nav.forward();
    for (NavMode m : {NavMode::Fly, NavMode::Walk, NavMode::Trackball}) {
        nav.setMode(m);
        EXPECT_EQ(nav.eye(), eye);
        EXPECT_EQ(nav.forward(), f);
    }
    expectNear(nav.center(), dvec3(0), 1e-9);
    expectNear(nav.forward(), glm::normalize(dvec3(-30, 30, -20)), 1e-12);
}

TEST(Navigator, TrackballOrbitsZoomsAndPans) {
    Navigator nav(Box{dvec3(-10), dvec3(10)}, dvec3(0, 0, 1));
    nav.lookAt(dvec3(40, 0, 10), dvec3(0));
    const double d = nav.distance();
    nav.drag(Navigator::kLeft, 120, -35, 720);  // orbit: the centre and the distance stay
    expectNear(nav.center(), dvec3(0), 1e-9);
    EXPECT_NEAR(glm::length(nav.eye()), d, 1e-9);
    EXPECT_GT(glm::length(nav.eye() - dvec3(40, 0, 10)), 1.0);
    nav.scroll(2);  // zoom in: closer, same centre
    EXPECT_NEAR(nav.distance(), d * 0.85 * 0.85, 1e-9);
    expectNear(nav.center(), dvec3(0), 1e-9);
    // Pan: eye and centre move together across the view, by the pixels' size at the centre's distance.
    const dvec3 eye = nav.eye(), f = nav.forward();
    nav.drag(Navigator::kRight, 72, 0, 720);
    const dvec3 moved = nav.eye() - eye;
    expectNear(nav.center(), moved, 1e-9);
    EXPECT_NEAR(glm::dot(moved, f), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(moved), 0.1 * 2 * nav.distance() * std::tan(glm::radians(kFovY) / 2), 1e-9);
    EXPECT_LT(glm::dot(moved, nav.right()), 0.0);  // the scene follows the cursor to the right
}

TEST(Navigator, FlyMovesAlongTheViewWalkOnTheLevel) {
    const Box b{dvec3(-50), dvec3(50)};
    for (const dvec3& up : {dvec3(0, 0, 1), dvec3(0, 1, 0)}) {
        Navigator nav(b, up);
        const dvec3 eye = 10.0 * up, center(10, 0, 0);  // 45 degrees down
        nav.lookAt(eye, center);
        nav.setMode(NavMode::Fly);
        const dvec3 f = nav.forward();
        MoveKeys k;
        k.forward = true;
        nav.move(k, 2.0);
        expectNear(nav.eye(), eye + 2.0 * nav.speed() * f, 1e-9);
        EXPECT_LT(glm::dot(nav.eye(), up), 10.0);  // flew down
        nav.lookAt(eye, center);
        nav.setMode(NavMode::Walk);
        k.right = true;
        k.up = true;  // no climbing while walking
        nav.move(k, 2.0);
        EXPECT_NEAR(glm::dot(nav.eye(), up), 10.0, 1e-9);  // the eye's height
        EXPECT_NEAR(glm::length(nav.eye() - eye), 2.0 * nav.speed(), 1e-9);
        k = MoveKeys{};
        k.fast = true;
        k.back = true;
        const dvec3 before = nav.eye();
        nav.move(k, 1.0);
        EXPECT_NEAR(glm::length(nav.eye() - before), 4.0 * nav.speed(), 1e-9);
    }
}

TEST(Navigator, WalkingStopsAtAWallAndFollowsTheGroundFlyingDoesNot) {
    // A floor at z = 0 and a wall at x in [10, 11]; the eye starts at x = 0, 1.7 above the floor, facing +x.
    auto root = make<Group>();
    auto mat = make<Material>();
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-50, -50, -1), dvec3(50, 50, 0)), mat));
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(10, -50, 0), dvec3(11, 50, 10)), mat));
    Scene scene(root);
    scene.update();
    const Box bound{dvec3(-50, -50, -1), dvec3(50, 50, 10)};
    ViewpointCollider walker(walkSettings(bound, dvec3(0, 0, 1)));
    for (NavMode mode : {NavMode::Walk, NavMode::Fly}) {
        Navigator nav(bound, dvec3(0, 0, 1));
        nav.setWalkMover(collidingWalk(scene, walker));
        nav.lookAt(dvec3(0, 0, 1.7), dvec3(20, 0, 1.7));
        nav.setMode(mode);
        MoveKeys k;
        k.forward = true;
        for (int f = 0; f < 200; ++f) nav.move(k, 1.0 / 60.0);  // 200 frames at the default speed: past the wall
        if (mode == NavMode::Walk) {
            EXPECT_LE(nav.eye().x, 10.0 - 0.3 + 1e-6);  // stopped a radius short of the wall
            EXPECT_GT(nav.eye().x, 5.0);                // having walked up to it
            EXPECT_NEAR(nav.eye().z, 1.7, 0.05);        // the eye's height above the floor
        } else {
            EXPECT_GT(nav.eye().x, 11.0);  // flying goes through
        }
    }
}

TEST(Navigator, PitchStopsShortOfStraightUpAndSpeedScales) {
    Navigator nav(Box{dvec3(-100), dvec3(100)}, dvec3(0, 0, 1));
    nav.setMode(NavMode::Fly);
    nav.drag(Navigator::kLeft, 0, -100000, 720);
    EXPECT_LT(glm::dot(nav.forward(), dvec3(0, 0, 1)), std::sin(glm::radians(89.5)));
    EXPECT_GT(glm::dot(nav.forward(), dvec3(0, 0, 1)), std::sin(glm::radians(88.5)));
    const Camera cam = nav.camera(640, 480);  // still a valid camera
    EXPECT_EQ(cam.width(), 640);
    const double s = nav.speed();
    EXPECT_NEAR(s, 0.1 * glm::length(dvec3(100)), 1e-9);  // a tenth of the scene's radius a second
    nav.scroll(1);
    EXPECT_NEAR(nav.speed(), s * 1.25, 1e-9);
    EXPECT_THROW(Navigator(Box{dvec3(-1), dvec3(1)}, dvec3(0)), std::invalid_argument);
    nav.setSpeed(1.5);  // a walking pace, whatever the scene's size
    EXPECT_EQ(nav.speed(), 1.5);
    nav.setSpeed(1e9);  // within the range scroll() keeps
    EXPECT_NEAR(nav.speed(), 10.0 * glm::length(dvec3(100)), 1e-9);
}

}  // namespace
