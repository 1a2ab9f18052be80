// What Mesh::closed() costs the first draw of a mesh (or the pager's thread): welding the positions and pairing
// the edges, per triangle, for boxes of 1,200 to 1.9 million triangles, closed and with one quad missing.
#include "sg/core/Mesh.h"
#include "sg/core/internal/MeshClosed.h"

#include <benchmark/benchmark.h>

namespace {

using namespace sg;

void closedBox(benchmark::State& state, bool holed) {
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1), dvec3(1), int(state.range(0)));
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < box->indexCount(); ++i) idx.push_back(box->index(i));
    if (holed) idx.resize(idx.size() - 6);  // a quad gone: an even count, so the pairing is what refuses it
    for (auto _ : state) benchmark::DoNotOptimize(boundsSolids(box->positions(), nullptr, idx.data(), idx.size()));
    state.counters["triangles"] = double(idx.size() / 3);
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(idx.size() / 3));
}

void BM_MeshClosed(benchmark::State& state) { closedBox(state, false); }
void BM_MeshClosedWithAHole(benchmark::State& state) { closedBox(state, true); }

}  // namespace

BENCHMARK(BM_MeshClosed)->Arg(10)->Arg(100)->Arg(400)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MeshClosedWithAHole)->Arg(100)->Unit(benchmark::kMillisecond);
