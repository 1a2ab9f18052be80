// factoryscan: a simulated terrestrial laser scan of the factory site (testbed/FactoryScan.h), written as LAS.
//
//   factoryscan --points N --out scan.las [--seed S] [--threads T]
//
// N may end in k, M or G (thousands, millions, billions): 1M, 100M, 2.5k. The LAS file's offset is the site's minimum
// corner and its scale a millimetre. Prints the points written, the rays fired, the seconds and the points per
// second. Exit 2, naming the problem, on bad arguments; 1 when the scan or the file fails.
#include "testbed/FactoryScan.h"
#include "loaders/points/Scan.h"
#include "testbed/Factory.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

namespace {

int usage(const std::string& problem) {
    std::fprintf(stderr,
                 "factoryscan: %s\n"
                 "usage: factoryscan --points N --out scan.las [--seed S] [--threads T]\n"
                 "       N may end in k, M or G: 1M, 100M\n",
                 problem.c_str());
    return 2;
}

// A count such as 20000, 1M or 2.5k; 0 when it is not one (or is above 10^12).
uint64_t count(const std::string& s) {
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(s.c_str(), &end);
    if (errno || end == s.c_str()) return 0;
    const std::string suffix(end);
    if (suffix == "k" || suffix == "K")
        v *= 1e3;
    else if (suffix == "m" || suffix == "M")
        v *= 1e6;
    else if (suffix == "g" || suffix == "G")
        v *= 1e9;
    else if (!suffix.empty())
        return 0;
    if (!(v >= 1.0 && v <= 1e12)) return 0;
    return uint64_t(std::llround(v));
}

// A whole number from 0 to 2^63 - 1, or -1.
long long whole(const std::string& s) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    return (errno || end == s.c_str() || *end || v < 0) ? -1 : v;
}

}  // namespace

int main(int argc, char** argv) {
    scenes::FactoryScanParams params;
    params.points = 0;
    std::string out;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a != "--points" && a != "--out" && a != "--seed" && a != "--threads") return usage("unknown option " + a);
        if (i + 1 >= argc) return usage(a + " needs a value");
        const std::string v = argv[++i];
        if (a == "--points") {
            params.points = count(v);
            if (params.points == 0) return usage("--points wants a count from 1 to 1000G such as 1M, not " + v);
        } else if (a == "--out") {
            out = v;
        } else if (a == "--seed") {
            const long long s = whole(v);
            if (s < 0) return usage("--seed wants a whole number, not " + v);
            params.seed = uint64_t(s);
        } else {
            const long long t = whole(v);
            if (t < 1 || t > 256) return usage("--threads wants a number from 1 to 256, not " + v);
            params.threads = int(t);
        }
    }
    if (params.points == 0) return usage("--points is needed");
    if (out.empty()) return usage("--out is needed");

    try {
        scenes::Factory f = scenes::buildFactory();
        sg::Scene scene(f.root);
        scene.update();
        sg::LasWriter las(out, 0.001);
        las.setOrigin(scene.image().box(0).min);  // the site's minimum corner: every switch's children are in it
        std::vector<sg::ScanPoint> batch;
        const scenes::FactoryScan scan =
            scenes::scanFactory(f, scene, params, [&](const std::vector<scenes::ScannedPoint>& points) {
                batch.resize(points.size());
                for (size_t k = 0; k < points.size(); ++k) {
                    batch[k].position = points[k].position;
                    batch[k].color = points[k].color;
                    batch[k].intensity = points[k].intensity;
                }
                las.write(batch);
            });
        las.close();
        std::printf("points written: %llu\n", (unsigned long long)scan.points);
        std::printf("rays fired: %llu (and %llu to size the grid)\n", (unsigned long long)scan.rays,
                    (unsigned long long)scan.pilotRays);
        std::printf("stations: %zu, grid %d x %d\n", scan.stations.size(), scan.azimuthSteps, scan.elevationSteps);
        std::printf("seconds: %.2f\n", scan.seconds);
        std::printf("points per second: %.0f\n", scan.seconds > 0.0 ? double(scan.points) / scan.seconds : 0.0);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "factoryscan: %s\n", e.what());
        return 1;
    }
    return 0;
}
