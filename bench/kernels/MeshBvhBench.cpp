// MeshBvh beside its naive twin (every triangle tested) and, when built with Embree, beside Embree 3's BVH
// (robust mode, float) on the same meshes and rays: nearest hit per ray, and build time.
#include "sg/intersect/MeshBvh.h"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>
#ifdef SGKIT_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace {

using namespace sg;

// A city building (10 x 10 quads a face, 1 200 triangles) or a dense grid-box (60 x 60, 43 200 triangles).
ref_ptr<Mesh> mesh(int which) { return makeBoxMesh(dvec3(-6, -6, 0), dvec3(6, 6, 40), which == 0 ? 10 : 60); }

struct Rays {
    std::vector<dvec3> o, d;
    explicit Rays(const Mesh& m, size_t n = 4096) {
        std::mt19937_64 g(3);
        std::uniform_real_distribution<double> u(-1, 1);
        const dvec3 c = m.box().center(), h = m.box().halfExtent();
        for (size_t k = 0; k < n; ++k) {
            const dvec3 dir = glm::normalize(dvec3(u(g), u(g), u(g)));
            const dvec3 from = c + dir * (2.0 * glm::length(h));
            const dvec3 to = c + dvec3(u(g) * h.x, u(g) * h.y, u(g) * h.z) * 1.2;  // some miss
            o.push_back(from);
            d.push_back(to - from);
        }
    }
};

void BM_MeshBvhNearest(benchmark::State& s) {
    auto m = mesh(int(s.range(0)));
    MeshBvh bvh(*m);
    Rays r(*m);
    size_t k = 0, hits = 0;
    for (auto _ : s) {
        MeshBvh::RayHit h;
        hits += bvh.nearest(r.o[k], r.d[k], kInf, h);
        k = (k + 1) % r.o.size();
    }
    benchmark::DoNotOptimize(hits);
    s.SetItemsProcessed(int64_t(s.iterations()));
}
BENCHMARK(BM_MeshBvhNearest)->Arg(0)->Arg(1);

// The naive twin: every triangle, the same watertight test.
void BM_BruteForceNearest(benchmark::State& s) {
    auto m = mesh(int(s.range(0)));
    MeshBvh bvh(*m);  // only for its triangle() accessor
    Rays r(*m);
    std::vector<dvec3> tris;
    for (uint32_t t = 0; t < m->triangleCount(); ++t) {
        dvec3 a, b, c;
        bvh.triangle(t, a, b, c);
        tris.insert(tris.end(), {a, b, c});
    }
    size_t k = 0, hits = 0;
    for (auto _ : s) {
        double best = kInf;
        MeshBvh::RayHit h;
        for (size_t t = 0; t < tris.size(); t += 3)
            if (MeshBvh::rayTriangle(r.o[k], r.d[k], best, tris[t], tris[t + 1], tris[t + 2], h)) best = h.t;
        hits += best < kInf;
        k = (k + 1) % r.o.size();
    }
    benchmark::DoNotOptimize(hits);
    s.SetItemsProcessed(int64_t(s.iterations()));
}
BENCHMARK(BM_BruteForceNearest)->Arg(0)->Arg(1);

void BM_MeshBvhBuild(benchmark::State& s) {
    auto m = mesh(int(s.range(0)));
    for (auto _ : s) {
        MeshBvh bvh(*m);
        benchmark::DoNotOptimize(bvh.nodeCount());
    }
    s.SetItemsProcessed(int64_t(s.iterations()) * m->triangleCount());
}
BENCHMARK(BM_MeshBvhBuild)->Arg(0)->Arg(1);

#ifdef SGKIT_HAVE_EMBREE
struct EmbreeMesh {
    // One device for the process (as an application would keep): builds are timed without its start-up.
    static RTCDevice device() {
        static RTCDevice d = rtcNewDevice("threads=1");
        return d;
    }
    RTCDevice dev = device();
    RTCScene scene = nullptr;
    explicit EmbreeMesh(const Mesh& m) {
        scene = rtcNewScene(dev);
        rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
        RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, m.positions().size()));
        for (size_t i = 0; i < m.positions().size(); ++i)
            v[3 * i] = m.positions()[i].x, v[3 * i + 1] = m.positions()[i].y, v[3 * i + 2] = m.positions()[i].z;
        auto* ix = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, m.triangleCount()));
        for (uint32_t i = 0; i < m.indexCount(); ++i) ix[i] = m.index(i);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene);
    }
    ~EmbreeMesh() { rtcReleaseScene(scene); }
};

void BM_EmbreeNearest(benchmark::State& s) {
    auto m = mesh(int(s.range(0)));
    EmbreeMesh e(*m);
    Rays r(*m);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    size_t k = 0, hits = 0;
    for (auto _ : s) {
        RTCRayHit rh{};
        rh.ray.org_x = float(r.o[k].x), rh.ray.org_y = float(r.o[k].y), rh.ray.org_z = float(r.o[k].z);
        rh.ray.dir_x = float(r.d[k].x), rh.ray.dir_y = float(r.d[k].y), rh.ray.dir_z = float(r.d[k].z);
        rh.ray.tnear = 0.0f, rh.ray.tfar = HUGE_VALF, rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(e.scene, &ctx, &rh);
        hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        k = (k + 1) % r.o.size();
    }
    benchmark::DoNotOptimize(hits);
    s.SetItemsProcessed(int64_t(s.iterations()));
}
BENCHMARK(BM_EmbreeNearest)->Arg(0)->Arg(1);

void BM_EmbreeBuild(benchmark::State& s) {
    auto m = mesh(int(s.range(0)));
    for (auto _ : s) {
        EmbreeMesh e(*m);
        benchmark::DoNotOptimize(e.scene);
    }
    s.SetItemsProcessed(int64_t(s.iterations()) * m->triangleCount());
}
BENCHMARK(BM_EmbreeBuild)->Arg(0)->Arg(1);
#endif

}  // namespace
