// Draw-list sort (radix on 64-bit state/depth keys) beside std::sort of the same keys.
#include "sg/cull/DrawList.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

namespace {

sg::DrawList makeList(size_t n, std::vector<sg::ref_ptr<sg::Mesh>>& meshes) {
    std::mt19937 g(3);
    for (int k = 0; k < 100; ++k) meshes.push_back(sg::make<sg::Mesh>());
    sg::DrawList l;
    for (size_t i = 0; i < n; ++i) {
        sg::DrawItem it;
        it.mesh = meshes[g() % meshes.size()].get();
        l.add(it, float(g() % 300000) * 0.01f);
    }
    return l;
}

void BM_DrawListRadixSort(benchmark::State& s) {
    std::vector<sg::ref_ptr<sg::Mesh>> meshes;
    sg::DrawList l = makeList(size_t(s.range(0)), meshes);
    for (auto _ : s) {
        l.sort();
        benchmark::DoNotOptimize(l.order.data());
    }
    s.SetItemsProcessed(int64_t(s.iterations()) * s.range(0));
}
BENCHMARK(BM_DrawListRadixSort)->Arg(30000);

// Naive twin: std::sort of indices by key.
void BM_DrawListStdSort(benchmark::State& s) {
    std::vector<sg::ref_ptr<sg::Mesh>> meshes;
    sg::DrawList l = makeList(size_t(s.range(0)), meshes);
    std::vector<uint32_t> order(l.items.size());
    for (auto _ : s) {
        for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return l.key(a) < l.key(b); });
        benchmark::DoNotOptimize(order.data());
    }
    s.SetItemsProcessed(int64_t(s.iterations()) * s.range(0));
}
BENCHMARK(BM_DrawListStdSort)->Arg(30000);

}  // namespace
