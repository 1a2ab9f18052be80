// The frustum kernel beside its naive twin and beside a plain flat scan written the obvious way, on
// the same random spheres against the same six planes (items per second).
#include "sg/core/Camera.h"
#include "sg/cull/internal/FrustumKernel.h"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace {

struct Data {
    std::vector<float> cx, cy, cz, r, ex, ey, ez;
    std::vector<uint8_t> out;
    std::array<sg::Plane, 6> planes;
    sg::kernel::Planes kp;
    explicit Data(size_t n) {
        std::mt19937 g(7);
        std::uniform_real_distribution<float> pos(-500, 500), rad(0.5f, 20);
        for (size_t i = 0; i < n; ++i) {
            cx.push_back(pos(g));
            cy.push_back(pos(g));
            cz.push_back(pos(g) * 0.1f);
            r.push_back(rad(g));
            ex.push_back(r.back() * 0.6f);
            ey.push_back(r.back() * 0.6f);
            ez.push_back(r.back() * 0.5f);
        }
        out.resize(n);
        sg::Camera cam;
        cam.setPerspective(60, 16.0 / 9.0, 1, 3000);
        cam.setLookAt(sg::dvec3(0, -600, 40), sg::dvec3(0, 0, 0), sg::dvec3(0, 0, 1));
        for (size_t k = 0; k < 6; ++k) {
            const sg::Plane& e = cam.eyePlanes()[k];
            planes[k] = sg::Plane{e.n, e.d - glm::dot(e.n, cam.eye())};
        }
        kp = sg::kernel::Planes::make(planes, sg::dvec3(0.0), 600.0, 0x3f);
    }
};

constexpr size_t kN = 1 << 16;

void BM_ClassifySpheres(benchmark::State& s) {
    Data d(kN);
    for (auto _ : s) {
        sg::kernel::classifySpheres(d.kp, d.cx.data(), d.cy.data(), d.cz.data(), d.r.data(), uint32_t(kN),
                                    d.out.data());
        benchmark::DoNotOptimize(d.out.data());
    }
    s.SetItemsProcessed(int64_t(s.iterations() * kN));
}
BENCHMARK(BM_ClassifySpheres);

void BM_ClassifyBoxes(benchmark::State& s) {
    Data d(kN);
    for (auto _ : s) {
        sg::kernel::classifyBoxes(d.kp, d.cx.data(), d.cy.data(), d.cz.data(), d.ex.data(), d.ey.data(), d.ez.data(),
                                  uint32_t(kN), d.out.data());
        benchmark::DoNotOptimize(d.out.data());
    }
    s.SetItemsProcessed(int64_t(s.iterations() * kN));
}
BENCHMARK(BM_ClassifyBoxes);

// Naive twin: double precision, one sphere at a time, early exit.
void BM_ClassifySpheresNaive(benchmark::State& s) {
    Data d(kN);
    for (auto _ : s) {
        for (size_t i = 0; i < kN; ++i)
            d.out[i] = sg::kernel::classifySphereNaive(d.planes, sg::dvec3(d.cx[i], d.cy[i], d.cz[i]), d.r[i]);
        benchmark::DoNotOptimize(d.out.data());
    }
    s.SetItemsProcessed(int64_t(s.iterations() * kN));
}
BENCHMARK(BM_ClassifySpheresNaive);

// Scalar masked test (the walk's test above the batches), over the same flat arrays.
void BM_SphereMaskedScalar(benchmark::State& s) {
    Data d(kN);
    for (auto _ : s) {
        for (size_t i = 0; i < kN; ++i)
            d.out[i] = uint8_t(sg::kernel::sphereMasked(d.kp, 0x3f, d.cx[i], d.cy[i], d.cz[i], d.r[i]));
        benchmark::DoNotOptimize(d.out.data());
    }
    s.SetItemsProcessed(int64_t(s.iterations() * kN));
}
BENCHMARK(BM_SphereMaskedScalar);

}  // namespace

namespace {
// The yardstick: a flat scan written the plainest way (visible or not, no inside bit), vectorized by
// the compiler with the same AVX2 clone the kernel gets. The kernel is held to at least half its speed.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("arch=haswell", "default")))
#endif
void flatScan(const sg::kernel::Planes& p, const float* __restrict cx, const float* __restrict cy,
              const float* __restrict cz, const float* __restrict r, size_t n, uint8_t* __restrict out) {
    for (size_t k = 0; k < n; ++k) {
        bool visible = true;
        for (int i = 0; i < 6; ++i) visible &= p.nx[i] * cx[k] + p.ny[i] * cy[k] + p.nz[i] * cz[k] + p.d[i] >= -r[k];
        out[k] = visible;
    }
}

void BM_FlatScanReference(benchmark::State& s) {
    Data d(kN);
    for (auto _ : s) {
        flatScan(d.kp, d.cx.data(), d.cy.data(), d.cz.data(), d.r.data(), kN, d.out.data());
        benchmark::DoNotOptimize(d.out.data());
    }
    s.SetItemsProcessed(int64_t(s.iterations() * kN));
}
BENCHMARK(BM_FlatScanReference);
}  // namespace
