// The LOD budget's cost per frame for 10,000 visible LODs of 3 levels (the target: <= 1 ms):
// the whole plan (values, prices, selection) inside a cull, and the selector alone on the same options.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/lod/DrawCostModel.h"
#include "sg/lod/LodSelector.h"

#include <benchmark/benchmark.h>

#include <random>

namespace {

using namespace sg;

// 100 x 100 LODs on a 10 m grid, seen whole from above; three levels of 1200, 300 and 12 triangles.
struct Grid {
    Scene scene;
    Camera cam;
    DrawCostModel model;
    static ref_ptr<Node> build() {
        auto mat = make<Material>();
        auto l0 = make<Geometry>(makeBoxMesh(dvec3(-3), dvec3(3), 10), mat);
        auto l1 = make<Geometry>(makeBoxMesh(dvec3(-3), dvec3(3), 5), mat);
        auto l2 = make<Geometry>(makeBoxMesh(dvec3(-3), dvec3(3), 1), mat);
        auto root = make<Group>();
        for (int i = 0; i < 100; ++i)
            for (int j = 0; j < 100; ++j) {
                auto lod = make<LOD>();
                lod->addChild(l0, 0, 300);
                lod->addChild(l1, 300, 800);
                lod->addChild(l2, 800, 5000);
                auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(i * 10.0, j * 10.0, 0.0)));
                t->addChild(lod);
                root->addChild(t);
            }
        return root;
    }
    Grid() : scene(build()) {
        scene.update();
        cam.setViewport(1280, 720);
        cam.setPerspective(60.0, 1280.0 / 720.0, 1.0, 5000.0);
        cam.setLookAt(dvec3(495, -400, 900), dvec3(495, 495, 0), dvec3(0, 0, 1));
        std::mt19937 g(1);  // a model that has seen some frames
        for (int k = 0; k < 50; ++k) {
            const double tris = 1e4 + double(g() % 200000), items = 100 + double(g() % 10000);
            model.update({tris, items, 0.0}, 1.0 + tris * 3e-4 + items * 2e-3);
        }
    }
};

void BM_LodBudgetPlan10k(benchmark::State& s) {
    Grid grid;
    CullTraversal cull;
    CullSettings set;
    set.lodBudget.enabled = true;
    set.lodBudget.model = &grid.model;
    set.lodBudget.budgetMs = 33.0;
    set.lodBudget.mayDrop = s.range(0) != 0;
    DrawList list;
    CullStats st;
    double selectMs = 0.0;
    for (auto _ : s) {
        cull.cull(grid.scene, grid.cam, set, list, st);
        selectMs += st.lodSelectMs;
    }
    if (st.lodObjects != 10000) s.SkipWithError("not every LOD is in view");
    s.counters["lods"] = double(st.lodObjects);
    s.counters["plan_ms"] = selectMs / double(s.iterations());
}
BENCHMARK(BM_LodBudgetPlan10k)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The selector alone: 10,000 objects of 3 options (random costs and benefits).
void BM_LodSelector10k(benchmark::State& s) {
    std::mt19937 g(2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<LodSelector::Option> opts(30000);
    std::vector<LodSelector::Object> objs(10000);
    for (size_t o = 0; o < objs.size(); ++o) {
        for (int k = 0; k < 3; ++k) opts[o * 3 + k] = {0.001 * (1 + k * 10) * u(g), 100.0 * (1 + k) * u(g)};
        objs[o] = {&opts[o * 3], 3, int(g() % 4) - 1};
    }
    LodSelector sel;
    for (auto _ : s) benchmark::DoNotOptimize(sel.select(objs, 20.0, 0.1).costMs);
}
BENCHMARK(BM_LodSelector10k)->Unit(benchmark::kMillisecond);

}  // namespace
