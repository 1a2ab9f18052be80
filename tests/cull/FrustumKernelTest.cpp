#include "sg/core/Camera.h"
#include "sg/cull/internal/FrustumKernel.h"

#include <gtest/gtest.h>

#include <random>

using namespace sg;

// The vectorized kernels against their naive double-precision twin: never "outside" where the twin says
// it is not, never "inside" where the twin says it is not; any difference only within the float slack.
TEST(FrustumKernel, AgreesWithItsNaiveTwin) {
    std::mt19937 g(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 20; ++trial) {
        Camera cam;
        cam.setPerspective(20 + 140 * (u(g) + 1) / 2, 1.5, 0.5, 800);
        const dvec3 origin(1e6 * u(g), 1e6 * u(g), 0);
        cam.setLookAt(origin + dvec3(50 * u(g), 50 * u(g), 10), origin + dvec3(200 * u(g), 200 * u(g), 0),
                      dvec3(0, 0, 1));
        std::array<Plane, 6> world;  // planes in coordinates relative to `origin`
        for (size_t k = 0; k < 6; ++k) {
            const Plane& e = cam.eyePlanes()[k];
            world[k] = Plane{e.n, e.d + glm::dot(e.n, origin - cam.eye())};
        }
        const size_t n = 4099;  // not a multiple of the vector width
        std::vector<float> cx(n), cy(n), cz(n), r(n), ex(n), ey(n), ez(n);
        for (size_t i = 0; i < n; ++i) {
            cx[i] = float(600 * u(g));
            cy[i] = float(600 * u(g));
            cz[i] = float(60 * u(g));
            r[i] = float(30 * (u(g) + 1));
            ex[i] = ey[i] = ez[i] = r[i] / std::sqrt(3.0f);
        }
        const auto kp = kernel::Planes::make(world, dvec3(0.0), 1000.0, 0x3f);
        std::vector<uint8_t> s(n), b(n);
        kernel::classifySpheres(kp, cx.data(), cy.data(), cz.data(), r.data(), uint32_t(n), s.data());
        kernel::classifyBoxes(kp, cx.data(), cy.data(), cz.data(), ex.data(), ey.data(), ez.data(), uint32_t(n),
                              b.data());
        int outside = 0, inside = 0;
        for (size_t i = 0; i < n; ++i) {
            const dvec3 c(cx[i], cy[i], cz[i]);
            const uint8_t ref = kernel::classifySphereNaive(world, c, r[i]);
            const uint8_t loose = kernel::classifySphereNaive(world, c, r[i] + 1e-3);
            const uint8_t tight = kernel::classifySphereNaive(world, c, std::max(0.0, r[i] - 1e-3));
            if (s[i] & kernel::kOutside) {
                EXPECT_EQ(ref, kernel::kOutside) << i;
            }
            if (ref == kernel::kOutside && tight == kernel::kOutside) {
                EXPECT_EQ(s[i], kernel::kOutside) << i;
            }
            if (loose == kernel::kInside) {
                EXPECT_EQ(s[i], kernel::kInside) << i;
            }
            if (s[i] == kernel::kInside) {
                EXPECT_NE(tight & kernel::kOutside, kernel::kOutside);
            }
            // A box inside its sphere: the box test may only cull more, never less.
            if (s[i] & kernel::kOutside) {
                EXPECT_TRUE(b[i] & kernel::kOutside) << i;
            }
            outside += ref == kernel::kOutside;
            inside += ref == kernel::kInside;
            // Masked scalar test agrees with the batch.
            const uint32_t m = kernel::sphereMasked(kp, 0x3f, cx[i], cy[i], cz[i], r[i]);
            EXPECT_EQ(m == kernel::kCulledMask, bool(s[i] & kernel::kOutside));
            EXPECT_EQ(m == 0u, bool(s[i] & kernel::kInside));
        }
        EXPECT_GT(outside, 0);
        EXPECT_GT(inside, 0);
    }
}

TEST(FrustumKernel, NonFiniteBoundsAreNeverCulled) {
    Camera cam;
    std::array<Plane, 6> world = cam.eyePlanes();
    const auto kp = kernel::Planes::make(world, dvec3(0.0), 10.0, 0x3f);
    const float nan = std::nanf(""), inf = HUGE_VALF;
    float cx[3] = {nan, 0, 1e6f}, cy[3] = {0, 0, 0}, cz[3] = {0, 1e6f, 0}, r[3] = {1, inf, inf};
    uint8_t out[3];
    kernel::classifySpheres(kp, cx, cy, cz, r, 3, out);
    for (uint8_t o : out) EXPECT_EQ(o, 0);
    kernel::classifyBoxes(kp, cx, cy, cz, r, r, r, 3, out);
    for (uint8_t o : out) EXPECT_EQ(o, 0);
}
