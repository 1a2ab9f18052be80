#include "sg/core/Camera.h"
#include "sg/core/Math.h"

#include <gtest/gtest.h>

using namespace sg;

TEST(Math, FrustumPlanesSeparateInsideFromOutside) {
    Camera cam;
    cam.setPerspective(60, 1.0, 1, 100);
    cam.setLookAt(dvec3(0, 0, 0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    auto inside = [&](dvec3 p) {
        for (const Plane& pl : cam.eyePlanes())
            if (pl.distance(p - cam.eye()) < 0) return false;
        return true;
    };
    EXPECT_TRUE(inside({0, 0, -50}));
    EXPECT_FALSE(inside({0, 0, -0.5}));  // before near
    EXPECT_FALSE(inside({0, 0, -101}));  // beyond far
    EXPECT_FALSE(inside({0, 40, -50}));  // above: tan(30) * 50 = 28.9
    EXPECT_TRUE(inside({0, 28, -50}));
    for (const Plane& pl : cam.eyePlanes()) EXPECT_NEAR(glm::length(pl.n), 1.0, 1e-12);
}

TEST(Math, TransformBoxIsTheBoxOfTheCorners) {
    const dmat4 m = glm::rotate(glm::translate(dmat4(1.0), dvec3(5, -2, 1)), 0.7, glm::normalize(dvec3(1, 2, 3)));
    const Box b{dvec3(-1, -2, -3), dvec3(2, 1, 0.5)};
    Box ref;
    for (int k = 0; k < 8; ++k)
        ref.expand(
            dvec3(m * dvec4(k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z, 1)));
    const Box t = transformBox(m, b);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(t.min[a], ref.min[a], 1e-12);
        EXPECT_NEAR(t.max[a], ref.max[a], 1e-12);
    }
}

TEST(Math, MaxScaleBoundsTheStretch) {
    EXPECT_NEAR(maxScale(glm::scale(dmat4(1.0), dvec3(2, 3, 0.5))), 3.0, 1e-9);
    EXPECT_NEAR(maxScale(glm::rotate(dmat4(1.0), 1.0, dvec3(0, 0, 1))), 1.0, 1e-9);
    dmat4 shear(1.0);
    shear[1][0] = 2.0;  // x += 2y
    const double s = maxScale(shear);
    for (double a = 0; a < 6.3; a += 0.01) {
        const dvec3 v(std::cos(a), std::sin(a), 0);
        EXPECT_LE(glm::length(dvec3(shear * dvec4(v, 0))), s + 1e-12);
    }
}

TEST(Math, NonFiniteElementIsNamed) {
    dmat4 m(1.0);
    EXPECT_EQ(nonFiniteElement(m), "");
    m[2][1] = std::nan("");
    EXPECT_EQ(nonFiniteElement(m), "element [2][1] is nan");
}

TEST(Math, NonInvertibleAffineIsRelativeToTheScale) {
    EXPECT_EQ(nonInvertibleAffine(dmat4(1.0)), "");
    EXPECT_EQ(nonInvertibleAffine(glm::scale(dmat4(1.0), dvec3(1e-6))), "");             // |det| 1e-18, yet invertible
    EXPECT_EQ(nonInvertibleAffine(glm::scale(dmat4(1.0), dvec3(1e6, 1e6, 1e-12))), "");  // thin, not singular
    dmat4 sheared(1.0);
    sheared[1] = dvec4(1.0, 1e-13, 0.0, 0.0);  // two axes almost parallel, at any scale
    EXPECT_EQ(nonInvertibleAffine(glm::scale(dmat4(1.0), dvec3(1e6)) * sheared).rfind("matrix is singular", 0), 0u);
    EXPECT_EQ(nonInvertibleAffine(glm::scale(dmat4(1.0), dvec3(1, 0, 1))).rfind("matrix is singular (det 0", 0), 0u);
    dmat4 m(1.0);
    m[3][0] = kInf;
    EXPECT_EQ(nonInvertibleAffine(m), "element [3][0] is inf");
}

TEST(Camera, BadParametersAreRefusedByName) {
    Camera cam;
    auto msg = [](auto f) {
        try {
            f();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(msg([&] { cam.setViewport(0, 100); }), "Camera::setViewport(): viewport 0x100 has no area");
    EXPECT_NE(msg([&] { cam.setPerspective(60, 1, 0, 10); }).find("Camera::setPerspective(): near 0"),
              std::string::npos);
    EXPECT_NE(msg([&] { cam.setPerspective(60, 1, 5, 5); }).find("far"), std::string::npos);
    EXPECT_NE(msg([&] { cam.setPerspective(180, 1, 1, 5); }).find("fovy 180"), std::string::npos);
    EXPECT_NE(msg([&] { cam.setProjection(dmat4(0.0)); }).find("Camera::setProjection(): projection is degenerate"),
              std::string::npos);
    dmat4 bad(1.0);
    bad[3][0] = INFINITY;
    EXPECT_NE(msg([&] { cam.setView(bad); }).find("Camera::setView(): element [3][0] is inf"), std::string::npos);
    EXPECT_NE(msg([&] { cam.setLookAt(dvec3(1), dvec3(1), dvec3(0, 0, 1)); }).find("eye equals centre"),
              std::string::npos);
    EXPECT_NE(msg([&] { cam.setLookAt(dvec3(0), dvec3(0, 0, 1), dvec3(0, 0, 1)); }).find("parallel"),
              std::string::npos);
}

TEST(Camera, ViewRotationKeepsTheEyeOutOfTheMatrix) {
    Camera cam;
    const dvec3 eye(1e7, -2e7, 300);
    cam.setLookAt(eye, eye + dvec3(1, 1, 0), dvec3(0, 0, 1));
    EXPECT_NEAR(glm::length(cam.eye() - eye), 0.0, 1e-6);
    EXPECT_EQ(cam.viewRotation()[3], dvec4(0, 0, 0, 1));
    EXPECT_NEAR(glm::dot(cam.viewDirection(), glm::normalize(dvec3(1, 1, 0))), 1.0, 1e-12);
}
