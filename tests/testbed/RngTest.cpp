// scenes::BasicRng gives, draw for draw, the streams the scenes were built from: the random scenes'
// (mt19937_64, top 53 bits), the factory's (mt19937, top 24 bits) and the occlusion tree cases' (splitmix64).
#include "testbed/Rng.h"

#include <gtest/gtest.h>

using scenes::BasicRng;

TEST(Rng, SixtyFourBitEngineGivesTheRandomScenesStream) {
    for (uint64_t seed : {0ull, 3ull, 12345ull, 20261122ull}) {
        std::mt19937_64 g(seed);
        scenes::Rng r(seed);
        for (int k = 0; k < 3000; ++k) {
            const double a = -50.0 + k % 7, b = a + 0.25 * (1 + k % 13);
            switch (k % 3) {
                case 0: ASSERT_EQ(r.uniform(a, b), a + (b - a) * double(g() >> 11) * (1.0 / 9007199254740992.0)); break;
                case 1: ASSERT_EQ(r.below(1 + k % 11), int(g() % uint64_t(1 + k % 11))); break;
                case 2:
                    ASSERT_EQ(r.chance(0.3), 0.0 + 1.0 * double(g() >> 11) * (1.0 / 9007199254740992.0) < 0.3);
                    break;
            }
        }
    }
}

TEST(Rng, ThirtyTwoBitEngineGivesTheFactorysStream) {
    for (uint32_t seed : {1u, 7u, 2024u, 0xfffffffeu}) {
        std::mt19937 g(seed);
        BasicRng<std::mt19937> r(seed);
        for (int k = 0; k < 3000; ++k) {
            const double a = k % 2 ? 0.0 : -3.5, b = k % 2 ? 1.0 : 12.0;
            ASSERT_EQ(r.uniform(a, b), a + (b - a) * double(g() >> 8) * (1.0 / 16777216.0));
        }
    }
}

TEST(Rng, SplitMixGivesTheOcclusionCasesStream) {
    EXPECT_EQ(scenes::SplitMix64(0)(), 0xe220a8397b1dcdafull);  // the generator's published first output
    for (uint64_t seed : {0ull, 7ull, 0x123456789abcdefull}) {
        uint64_t s = seed;
        auto next = [&s] {
            uint64_t z = (s += 0x9e3779b97f4a7c15ull);
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull, z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
            return z ^ (z >> 31);
        };
        BasicRng<scenes::SplitMix64> r(seed);
        for (int k = 0; k < 3000; ++k) {
            if (k % 2)
                ASSERT_EQ(r.uniform(-2.0, 5.0), -2.0 + 7.0 * double(next() >> 11) * 0x1p-53);
            else
                ASSERT_EQ(r.below(1000), int(next() % 1000u));
        }
    }
}

TEST(Rng, UniformStaysInItsHalfOpenRange) {
    BasicRng<std::mt19937> narrow(5);
    scenes::Rng wide(5);
    for (int k = 0; k < 100000; ++k) {
        const double u = narrow.uniform(), w = wide.uniform(), l = wide.logUniform(0.01, 100.0);
        ASSERT_TRUE(u >= 0.0 && u < 1.0) << u;
        ASSERT_TRUE(w >= 0.0 && w < 1.0) << w;
        ASSERT_TRUE(l >= 0.01 * (1 - 1e-12) && l < 100.0 * (1 + 1e-12)) << l;
    }
}
