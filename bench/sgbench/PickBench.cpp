// sgbench pick: picking and viewpoint collision on the city scene (docs/scenes.md). Pick rays through random pixels of
// the orbit path's frames (LOD levels as each frame draws them); collision steps of a random walk at up to 100 m/s at
// 60 Hz; time per ray and per step; then the picks checked against an id-buffer render.
#include "sg/intersect/PickSet.h"
#include "sg/intersect/ViewpointCollider.h"
#include "sgbench/Bench.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/PickAccuracy.h"
#include "testbed/RandomScene.h"

#include <chrono>
#include <stdexcept>

namespace bench {

namespace {
using Clock = std::chrono::steady_clock;
double usSince(Clock::time_point t) { return std::chrono::duration<double, std::micro>(Clock::now() - t).count(); }
}  // namespace

int runPick(const Args& a) {
    if (a.flag("features")) return runPickFeatures(a);
    const std::string sceneName = a.str("scene", "city");
    if (sceneName != "city")
        throw std::invalid_argument("sgbench pick: --scene must be city (got '" + sceneName + "')");
    const int n = int(a.num("n", 316));
    if (n < 1 || n > 1000) throw std::invalid_argument("sgbench pick: --n " + std::to_string(n) + " is not in 1..1000");
    const int perFrame = int(a.num("rays-per-frame", 100));
    const int steps = int(a.num("steps", 10000));
    const int agreementViews = int(a.num("agreement-views", 20));
    if (perFrame < 1 || steps < 1 || agreementViews < 0)
        throw std::invalid_argument(
            "sgbench pick: --rays-per-frame and --steps must be at least 1, --agreement-views at least 0");

    sg::Scene scene(scenes::buildCity({n, false}));
    scene.update();
    scenes::Rng rng(uint64_t(a.num("seed", 1)));

    // Rays: random pixels of every orbit frame (1280 x 720), as a pick through that frame's camera.
    std::vector<sg::Camera> cams;
    std::vector<sg::Ray> rays;
    std::vector<int> rayCam;
    for (int f = 0; f < scenes::kOrbitFrames; ++f) {
        cams.push_back(scenes::cityOrbitCamera(n, f));
        for (int k = 0; k < perFrame; ++k) {
            rays.push_back(sg::pixelRay(cams.back(), rng.uniform(0, 1280), rng.uniform(0, 720)));
            rayCam.push_back(f);
        }
    }
    sg::IntersectTraversal isect;
    uint64_t geometriesTested = 0, entriesVisited = 0;
    auto pickAll = [&](std::vector<double>* us, uint64_t* hits) {
        for (size_t r = 0; r < rays.size(); ++r) {
            sg::QueryOptions opt;
            opt.camera = &cams[size_t(rayCam[r])];
            opt.lod = sg::LodChoice::AsDrawn;
            sg::Hit h;
            const auto t0 = Clock::now();
            const bool hit = isect.intersect(scene, rays[r], opt, h);
            if (us) us->push_back(usSince(t0));
            if (hits && hit) ++*hits;
            if (us)
                geometriesTested += isect.lastStats().geometriesTested,
                    entriesVisited += isect.lastStats().entriesVisited;
        }
    };
    const auto w0 = Clock::now();
    pickAll(nullptr, nullptr);  // warm-up: the BVHs are built on first use
    const double firstPassMs = usSince(w0) / 1000.0;
    std::vector<double> pickUs;
    uint64_t hits = 0;
    pickAll(&pickUs, &hits);

    // Collision: random walk over the city (heading to a random point, new speed in [0, 100] m/s every 30 steps).
    sg::ViewpointSettings vs;
    vs.radius = 0.3;
    sg::ViewpointCollider col(vs);
    const double L = 20.0 * n;
    auto randomPoint = [&] { return sg::dvec3(rng.uniform(0, L), rng.uniform(0, L), rng.uniform(0.5, 60)); };
    sg::dvec3 pos(20.0 * (n / 2), 10.0, 1.7), target = pos;
    double speed = 0.0;
    std::vector<double> collideUs;
    uint64_t contactSteps = 0;
    for (int s = 0; s < steps; ++s) {
        if (s % 30 == 0) target = randomPoint(), speed = rng.uniform(0, 100);
        const sg::dvec3 dir = target - pos + sg::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const double len = glm::length(dir);
        const sg::dvec3 step = len > 0 ? dir / len * (speed / 60.0) : sg::dvec3(0.0);
        const auto t0 = Clock::now();
        pos = col.move(scene, pos, step);
        collideUs.push_back(usSince(t0));
        if (col.lastStats().contacts) ++contactSteps;
    }

    Json j;
    j.add("command", "pick").add("scene", "city").addInt("n", n);
    j.addInt("rays", long(pickUs.size())).add("hit_fraction", double(hits) / double(pickUs.size()));
    j.add("pick_us_median", median(pickUs)).add("pick_us_p95", percentile(pickUs, 0.95));
    j.add("geometries_per_pick", double(geometriesTested) / double(pickUs.size()));
    j.add("entries_per_pick", double(entriesVisited) / double(pickUs.size()));
    j.add("first_pass_ms", firstPassMs).addInt("bvhs", long(isect.bvhCache().size()));
    j.addInt("steps", steps).add("contact_fraction", double(contactSteps) / steps);
    j.add("collide_us_median", median(collideUs)).add("collide_us_p95", percentile(collideUs, 0.95));
    if (agreementViews > 0) {
        // Each geometry its own flat colour, drawn at 320 x 180; 500 random pixels per view picked.
        const accuracy::IdMap ids = accuracy::assignIdColors(scene.root());
        scene.update();
        accuracy::PickHarness h(320, 180);
        const accuracy::PickAgreement r =
            h.run(scene, ids, accuracy::cityViews(n, agreementViews, 7, 320, 180), 500, 3);
        j.add("pick_agreement", r.rate()).addInt("agreement_pixels", long(r.compared));
    }
    j.print(a);
    return 0;
}

}  // namespace bench
