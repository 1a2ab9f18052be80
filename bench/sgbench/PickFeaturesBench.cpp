// sgbench pick --features: what reading a pick's features costs. The city built twice, with its buildings as
// features (CityOptions::features) and without; rays through random pixels of the orbit's frames. On the city with
// features each pick is followed by sg::featuresAt and every property rendered to text as sgview's panel does; on
// the other the pick alone. The two alternate pass by pass in one process (A B A B ...), each pass every ray once:
// medians of microseconds per pick, and the median of the rounds' ratios.
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/PickSet.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"
#include "testbed/RandomScene.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double usSince(Clock::time_point t) { return std::chrono::duration<double, std::micro>(Clock::now() - t).count(); }

// Pick rays, each with the camera whose frame it goes through (AsDrawn LOD: the levels that frame draws).
struct Rays {
    std::vector<sg::Camera> cams;
    std::vector<sg::Ray> rays;
    std::vector<size_t> cam;
};

Rays orbitRays(int n, int perFrame, uint64_t seed) {
    scenes::Rng rng(seed);
    Rays r;
    for (int f = 0; f < scenes::kOrbitFrames; ++f) {
        r.cams.push_back(scenes::cityOrbitCamera(n, f));
        for (int k = 0; k < perFrame; ++k) {
            r.rays.push_back(sg::pixelRay(r.cams.back(), rng.uniform(0, 1280), rng.uniform(0, 720)));
            r.cam.push_back(size_t(f));
        }
    }
    return r;
}

// What sgview's panel shows of a pick: each feature's class and id, then every property as "id value". Returns the
// text's length, which the pass adds up so that the work is not optimised away.
size_t featureText(const sg::HitFeatures& f) {
    std::string s;
    for (const sg::FeatureAtHit& x : f.features) {
        s += x.classId + " " + std::to_string(x.featureId);
        for (const auto& [id, v] : x.properties) s += "\n" + id + " " + v.toString();
    }
    return s.size();
}

struct Pass {
    std::vector<double> us;      // per pick, the intersection and the features read (typed values)
    std::vector<double> textUs;  // per pick, everything the pass does for it: the values rendered to text too
    std::vector<double> pickUs;  // per pick, the intersection alone
    uint64_t hits = 0, withProperties = 0;
    size_t chars = 0;
};

// Every ray once; with `features`, each hit's features read (featuresAt: the ratio's target) and then rendered to
// text (timed apart: what a viewer's panel adds).
Pass pickPass(sg::IntersectTraversal& isect, const sg::Scene& scene, const Rays& r, bool features) {
    Pass p;
    p.us.reserve(r.rays.size());
    p.textUs.reserve(r.rays.size());
    p.pickUs.reserve(r.rays.size());
    for (size_t i = 0; i < r.rays.size(); ++i) {
        sg::QueryOptions opt;
        opt.camera = &r.cams[r.cam[i]];
        opt.lod = sg::LodChoice::AsDrawn;
        sg::Hit h;
        const auto t0 = Clock::now();
        const bool hit = isect.intersect(scene, r.rays[i], opt, h);
        const double pickOnly = usSince(t0);
        double read = pickOnly;
        if (hit && features) {
            const sg::HitFeatures f = sg::featuresAt(h);
            read = usSince(t0);
            p.chars += featureText(f);
            if (std::any_of(f.features.begin(), f.features.end(),
                            [](const sg::FeatureAtHit& x) { return !x.properties.empty(); }))
                ++p.withProperties;
        }
        p.us.push_back(read);
        p.textUs.push_back(usSince(t0));
        p.pickUs.push_back(pickOnly);
        if (hit) ++p.hits;
    }
    return p;
}

void append(std::vector<double>& to, const std::vector<double>& from) { to.insert(to.end(), from.begin(), from.end()); }

}  // namespace

int runPickFeatures(const Args& a) {
    const int n = int(a.num("n", 316));
    if (n < 1 || n > 1000)
        throw std::invalid_argument("sgbench pick --features: --n " + std::to_string(n) + " is not in 1..1000");
    const int perFrame = int(a.num("rays-per-frame", 100)), rounds = int(a.num("rounds", 5));
    if (perFrame < 1 || rounds < 1)
        throw std::invalid_argument("sgbench pick --features: --rays-per-frame and --rounds must be at least 1");

    scenes::CityOptions plainOpt, featureOpt;
    plainOpt.n = featureOpt.n = n;
    featureOpt.features = true;
    sg::Scene plain(scenes::buildCity(plainOpt)), featured(scenes::buildCity(featureOpt));
    plain.update();
    featured.update();
    const Rays rays = orbitRays(n, perFrame, uint64_t(a.num("seed", 1)));

    // A traversal per city (each keeps its meshes' BVHs); a first pass on each builds them.
    sg::IntersectTraversal plainIsect, featureIsect;
    pickPass(plainIsect, plain, rays, false);
    pickPass(featureIsect, featured, rays, true);

    std::vector<double> plainUs, featureUs, textUs, featurePickUs, ratio, textRatio;
    Pass last;
    uint64_t plainHits = 0;
    size_t chars = 0;
    for (int r = 0; r < rounds; ++r) {
        const Pass p = pickPass(plainIsect, plain, rays, false);
        last = pickPass(featureIsect, featured, rays, true);
        append(plainUs, p.us);
        append(featureUs, last.us);
        append(textUs, last.textUs);
        textRatio.push_back(median(last.textUs) / median(p.us));
        append(featurePickUs, last.pickUs);
        ratio.push_back(median(last.us) / median(p.us));
        plainHits = p.hits;
        chars += last.chars;
    }
    const double count = double(rays.rays.size());
    Json j;
    j.add("command", "pick").add("mode", "features").add("scene", "city").addInt("n", n);
    j.addInt("rays", long(rays.rays.size())).addInt("rounds", rounds);
    j.add("hit_fraction_plain", double(plainHits) / count).add("hit_fraction_features", double(last.hits) / count);
    j.add("hits_with_properties_fraction", last.hits ? double(last.withProperties) / double(last.hits) : 0.0);
    j.add("text_chars_per_hit", last.hits ? double(chars) / double(rounds) / double(last.hits) : 0.0);
    j.add("pick_us_median_plain", median(plainUs)).add("pick_us_median_features", median(featureUs));
    j.add("pick_us_p95_plain", percentile(plainUs, 0.95)).add("pick_us_p95_features", percentile(featureUs, 0.95));
    j.add("intersect_us_median_features", median(featurePickUs));
    j.add("pick_us_median_features_text", median(textUs));
    j.add("features_ratio", median(ratio));
    j.add("features_ratio_min", *std::min_element(ratio.begin(), ratio.end()));
    j.add("features_ratio_max", *std::max_element(ratio.begin(), ratio.end()));
    j.add("features_text_ratio", median(textRatio));  // and every value rendered to text, as sgview's panel
    j.print(a);
    // A pick that reads no properties on the city with features measures nothing.
    if (last.withProperties == 0) {
        std::fprintf(stderr, "sgbench pick --features: no hit read a building's properties\n");
        return 1;
    }
    return 0;
}

}  // namespace bench
