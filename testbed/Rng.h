// Random numbers for the testbed's scenes and the tests: one interface over the engine, taking only its raw
// stream (no std distributions), so a seed gives the same scene with every standard library.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace scenes {

// splitmix64 (Steele, Lea and Flood; Vigna's constants): cheap to seed, so a random case reruns alone from
// its seed. A standard uniform random bit generator.
class SplitMix64 {
public:
    using result_type = uint64_t;
    explicit SplitMix64(uint64_t seed = 0) : s_(seed) {}
    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }
    result_type operator()() {
        uint64_t z = (s_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }

private:
    uint64_t s_;
};

// Engine: a 64-bit generator (its top 53 bits make a double in [0, 1)) or a 32-bit one (its top 24 bits).
template <class Engine>
class BasicRng {
    static_assert(Engine::min() == 0, "BasicRng: the engine's stream must start at 0");
    static_assert(Engine::max() == 0xffffffffull || Engine::max() == ~0ull, "BasicRng: a 32- or 64-bit engine");
    static constexpr bool kWide = Engine::max() == ~0ull;

public:
    explicit BasicRng(uint64_t seed) : g_(typename Engine::result_type(seed)) {}

    // In [a, b): a + (b - a) * u, u on a grid of 2^-53 (64-bit engine) or 2^-24 (32-bit), from one draw.
    double uniform(double a = 0.0, double b = 1.0) {
        if constexpr (kWide)
            return a + (b - a) * double(uint64_t(g_()) >> 11) * 0x1p-53;
        else
            return a + (b - a) * double(uint64_t(g_()) >> 8) * 0x1p-24;
    }
    // Log-uniform in [a, b) for positive a and b: every factor of ten as likely.
    double logUniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
    // In [0, n) for n > 0: the draw modulo n (biased by at most n / 2^32, which no scene here notices).
    int below(int n) { return int(uint64_t(g_()) % uint64_t(n)); }
    bool chance(double p) { return uniform(0, 1) < p; }

    Engine& engine() { return g_; }

private:
    Engine g_;
};

// The random scenes' stream (testbed/RandomScene.h and the scenes and tests that take its Rng).
using Rng = BasicRng<std::mt19937_64>;

}  // namespace scenes
