#include "testbed/FactoryScan.h"

#include "nodes/Geometry.h"
#include "sg/intersect/IntersectTraversal.h"
#include "testbed/FactoryWalk.h"
#include "testbed/Rng.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace scenes {

using sg::dvec3;

namespace {

constexpr double kMinElevation = -60.0, kMaxElevation = 90.0;  // degrees: a panorama's rows, both ends included
constexpr double kEyeHeight = 1.7;                             // the walk path's eyes above the ground
constexpr double kScannerHeight = 1.5;
constexpr double kSiteMargin = 25.0;  // site stations: metres outside the bound of the buildings' boxes
constexpr double kClearance = 1.0;    // a site station has no surface nearer than this (not inside a car or a tree)
constexpr int kPilotAzimuths = 45, kPilotElevations = 20;  // 8 degrees: enough to measure how many rays return
constexpr double kFalloffRange = 50.0;                     // metres: the intensity halves there at normal incidence
constexpr int kRaysPerBatch = 16384;  // a worker's unit: small enough to balance, large enough to amortise the locks
constexpr double kNoiseCut = 4.0;     // deviations: a return further off is redrawn

// A panorama's grid: columns over 360 degrees of azimuth, rows from kMinElevation to kMaxElevation.
struct Grid {
    int azimuths = 1, elevations = 2;
    uint64_t rays() const { return uint64_t(azimuths) * uint64_t(elevations); }
};

// Columns [first, first + count) of one station's panorama: the unit the workers take and the sink receives.
struct Batch {
    size_t station;
    int first, count;
};

// What every worker reads and none writes.
struct Sweep {
    const sg::Scene* scene;
    const std::vector<dvec3>* stations;
    Grid grid;
    double noise, maxRange;
    uint64_t seed;
};

using NoiseRng = BasicRng<SplitMix64>;

dvec3 direction(const Grid& g, int column, int row) {
    const double az = 2.0 * M_PI * column / g.azimuths;
    const double el = glm::radians(kMinElevation + (kMaxElevation - kMinElevation) * row / (g.elevations - 1));
    return dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

// A stream of its own for every batch, from the seed and where the batch is: the noise does not depend on which
// worker scans it, nor when.
uint64_t batchSeed(uint64_t seed, size_t station, int column) {
    SplitMix64 a(seed);
    SplitMix64 b(a() ^ uint64_t(station));
    SplitMix64 c(b() ^ uint64_t(column));
    return c();
}

// A standard normal deviate (Box-Muller), cut at kNoiseCut so that every return stays near its surface.
double gaussian(NoiseRng& rng) {
    for (;;) {
        const double u1 = 1.0 - rng.uniform(), u2 = rng.uniform();  // u1 in (0, 1]: its log is finite
        const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
        if (std::abs(z) <= kNoiseCut) return z;
    }
}

uint8_t byte(float x) { return uint8_t(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); }

// The material's base colour times the mesh's vertex colour interpolated at the hit (textures are not sampled).
glm::u8vec4 colorAt(const sg::Hit& h) {
    const sg::Material* material = h.geometry->material();
    sg::vec4 c = material ? material->baseColor : sg::vec4(0.8f, 0.8f, 0.8f, 1.0f);  // Material's default
    const sg::Mesh* mesh = h.geometry->mesh();
    if (mesh && mesh->colors().size() == mesh->positions().size() && h.primitive < mesh->triangleCount()) {
        const std::vector<sg::vec4>& cs = mesh->colors();
        const size_t i = 3 * size_t(h.primitive);
        const sg::vec4 v = cs[mesh->index(i)] * float(1.0 - h.u - h.v) + cs[mesh->index(i + 1)] * float(h.u) +
                           cs[mesh->index(i + 2)] * float(h.v);
        c *= v;
    }
    return {byte(c.r), byte(c.g), byte(c.b), 255};
}

// Brightest at normal incidence and close by, as a scanner's return strength.
uint16_t intensityAt(const sg::Hit& h, const dvec3& dir, double range) {
    const double incidence = std::abs(glm::dot(h.normal, dir));
    const double falloff = 1.0 / (1.0 + (range / kFalloffRange) * (range / kFalloffRange));
    return uint16_t(std::lround(std::clamp(65535.0 * incidence * falloff, 0.0, 65535.0)));
}

void sweepBatch(const Sweep& s, const Batch& b, sg::IntersectTraversal& traversal, std::vector<ScannedPoint>& out) {
    out.clear();
    NoiseRng rng(batchSeed(s.seed, b.station, b.first));
    const dvec3 origin = (*s.stations)[b.station];
    sg::QueryOptions options;
    options.lod = sg::LodChoice::Highest;
    sg::Hit hit;
    for (int c = b.first; c < b.first + b.count; ++c)
        for (int r = 0; r < s.grid.elevations; ++r) {
            const dvec3 d = direction(s.grid, c, r);
            if (!traversal.intersect(*s.scene, sg::Ray{origin, d, s.maxRange}, options, hit)) continue;
            const double range = hit.t + s.noise * gaussian(rng);
            if (!(range > 0.0)) continue;
            out.push_back({origin + d * range, colorAt(hit), intensityAt(hit, d, hit.t)});
        }
}

std::vector<Batch> batchesOf(size_t stations, const Grid& g) {
    const int columns = std::max(1, kRaysPerBatch / g.elevations);
    std::vector<Batch> out;
    for (size_t s = 0; s < stations; ++s)
        for (int c = 0; c < g.azimuths; c += columns) out.push_back({s, c, std::min(columns, g.azimuths - c)});
    return out;
}

// The batches taken, and those done but not yet handed to the sink; `window` bounds how far the workers run ahead
// of the sink, which bounds the memory a large scan holds.
struct Queue {
    std::mutex mutex;
    std::condition_variable changed;
    size_t next = 0, emitted = 0, window = 0;
    std::map<size_t, std::vector<ScannedPoint>> done;
    std::exception_ptr error;
    bool stop = false;
};

// A worker: its own traversal (IntersectTraversal keeps scratch state and a BVH cache; the Scene is only read).
void work(const Sweep& s, const std::vector<Batch>& batches, Queue& q) {
    sg::IntersectTraversal traversal;
    for (;;) {
        size_t k;
        {
            std::unique_lock<std::mutex> lock(q.mutex);
            q.changed.wait(lock, [&] { return q.stop || q.next >= batches.size() || q.next < q.emitted + q.window; });
            if (q.stop || q.next >= batches.size()) return;
            k = q.next++;
        }
        std::vector<ScannedPoint> points;
        try {
            sweepBatch(s, batches[k], traversal, points);
        } catch (...) {
            std::lock_guard<std::mutex> lock(q.mutex);
            if (!q.error) q.error = std::current_exception();
            q.stop = true;
            q.changed.notify_all();
            return;
        }
        std::lock_guard<std::mutex> lock(q.mutex);
        q.done.emplace(k, std::move(points));
        q.changed.notify_all();
    }
}

// Stops and joins the workers however the sweep ends (a worker's error, or the sink's).
struct Workers {
    Queue& q;
    std::vector<std::thread> threads;
    ~Workers() {
        {
            std::lock_guard<std::mutex> lock(q.mutex);
            q.stop = true;
        }
        q.changed.notify_all();
        for (std::thread& t : threads) t.join();
    }
};

// Scans the batches on `workers` threads and hands each one's points to the sink on this thread, in batch order;
// returns the points handed over.
uint64_t runOrdered(const Sweep& s, const std::vector<Batch>& batches, int workers, const ScanSink& sink) {
    Queue q;
    const size_t n = std::min(size_t(workers), batches.size());
    q.window = 2 * n + 2;
    Workers pool{q, {}};
    for (size_t i = 0; i < n; ++i) pool.threads.emplace_back(work, std::cref(s), std::cref(batches), std::ref(q));
    uint64_t points = 0;
    for (size_t k = 0; k < batches.size(); ++k) {
        std::vector<ScannedPoint> batch;
        {
            std::unique_lock<std::mutex> lock(q.mutex);
            q.changed.wait(lock, [&] { return q.error || q.done.count(k) != 0; });
            if (q.error) std::rethrow_exception(q.error);
            auto it = q.done.find(k);
            batch = std::move(it->second);
            q.done.erase(it);
            q.emitted = k + 1;
        }
        q.changed.notify_all();
        points += batch.size();
        if (sink) sink(batch);
    }
    return points;
}

// A grid whose panoramas fire about `rays` rays each, its azimuth and elevation steps about equal.
Grid gridFor(double rays) {
    rays = std::clamp(rays, 2.0, 1e12);
    const double step = std::sqrt(360.0 * (kMaxElevation - kMinElevation) / rays);
    Grid g;
    g.azimuths = std::max(1, int(std::lround(360.0 / step)));
    g.elevations = std::max(2, int(std::lround(rays / g.azimuths)));
    return g;
}

// Evenly along the walking legs of the walkthrough path (outside, into a workshop, along its machines, out).
std::vector<dvec3> walkStations(Factory& f, sg::Scene& scene, int count) {
    if (count == 0) return {};
    const WalkPath path = buildWalkPath(f, scene, std::max(40, 2 * count));
    std::vector<dvec3> ground;
    for (const PathFrame& p : path.frames)
        if (p.walking) ground.push_back(p.eye - dvec3(0.0, 0.0, kEyeHeight));
    if (ground.empty()) throw std::logic_error("scanFactory(): the walk path has no walking frame");
    std::vector<dvec3> out;
    for (int i = 0; i < count; ++i) {
        const size_t k = std::min(ground.size() - 1, size_t((i + 0.5) * double(ground.size()) / count));
        out.push_back(ground[k] + dvec3(0.0, 0.0, kScannerHeight));
    }
    return out;
}

// On an ellipse kSiteMargin outside the bound of the buildings' boxes, each moved outward in 5 m steps until
// nothing is within kClearance (a few tries; then it stays where it is).
std::vector<dvec3> siteStations(const Factory& f, const sg::Scene& scene, int count) {
    sg::Box all;
    for (const FactoryBuilding& b : f.buildings) all.expand(b.box);
    const dvec3 c = all.center(), half = all.halfExtent();
    sg::IntersectTraversal probe;
    const sg::QueryOptions options;
    std::vector<sg::Hit> nearby;
    std::vector<dvec3> out;
    for (int i = 0; i < count; ++i) {
        const double a = 2.0 * M_PI * (i + 0.5) / count;
        for (int tries = 0;; ++tries) {
            const double x = c.x + (half.x + kSiteMargin + 5.0 * tries) * std::cos(a);
            const double y = c.y + (half.y + kSiteMargin + 5.0 * tries) * std::sin(a);
            const dvec3 p(x, y, f.terrainHeight(x, y) + kScannerHeight);
            probe.intersectSphere(scene, p, kClearance, options, nearby);
            if (nearby.empty() || tries == 8) {
                out.push_back(p);
                break;
            }
        }
    }
    return out;
}

void checkParams(const FactoryScanParams& p) {
    auto fail = [](const std::string& what) { throw std::invalid_argument("scanFactory(): " + what); };
    if (p.points == 0) fail("no points wanted");
    if (p.walkStations < 0 || p.siteStations < 0)
        fail("station counts " + std::to_string(p.walkStations) + " and " + std::to_string(p.siteStations));
    if (p.walkStations + p.siteStations == 0) fail("no stations");
    if (!(p.rangeNoise >= 0.0 && std::isfinite(p.rangeNoise)))
        fail("range noise " + std::to_string(p.rangeNoise) + " is negative or not finite");
    if (!(p.maxRange > 0.0 && std::isfinite(p.maxRange)))
        fail("max range " + std::to_string(p.maxRange) + " is not positive and finite");
    if (p.threads < 0) fail("threads " + std::to_string(p.threads));
}

}  // namespace

FactoryScan scanFactory(Factory& f, sg::Scene& scene, const FactoryScanParams& params, const ScanSink& sink) {
    checkParams(params);
    FactoryScan scan;
    scan.stations = walkStations(f, scene, params.walkStations);
    // Everything at once, as on the site: the switches that hide what a closed building hides are a drawing matter.
    f.outside->setAll(true);
    for (FactoryWorkshop& w : f.workshops) w.interior->setAll(true);
    scene.update();
    const std::vector<dvec3> site = siteStations(f, scene, params.siteStations);
    scan.stations.insert(scan.stations.end(), site.begin(), site.end());

    const int workers = params.threads > 0 ? params.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    const size_t stations = scan.stations.size();
    const auto t0 = std::chrono::steady_clock::now();
    Sweep s{&scene,          &scan.stations, Grid{kPilotAzimuths, kPilotElevations}, params.rangeNoise,
            params.maxRange, params.seed};
    // The share of rays that return (the sky gives nothing) sizes the grid for the points wanted.
    const uint64_t pilotPoints = runOrdered(s, batchesOf(stations, s.grid), workers, nullptr);
    scan.pilotRays = s.grid.rays() * stations;
    const double returning = pilotPoints > 0 ? double(pilotPoints) / double(scan.pilotRays) : 1.0;
    s.grid = gridFor(double(params.points) / returning / double(stations));

    scan.azimuthSteps = s.grid.azimuths;
    scan.elevationSteps = s.grid.elevations;
    scan.rays = s.grid.rays() * stations;
    scan.points = runOrdered(s, batchesOf(stations, s.grid), workers, sink);
    scan.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return scan;
}

}  // namespace scenes
