// sgtile: writes a scene as an OGC 3D Tiles 1.1 tile pyramid (tileset.json and tiles/*.glb).
//
//   sgtile --city N --out DIR [--max-triangles T] [--proxies exact|simplified] [--implicit] [--features]
//   sgtile INPUT.glb|.gltf --out DIR [...]
//   sgtile --points SCAN.las|.ply --out DIR [--pnts] [--max-points-per-tile N] [--shard I/N] [--merge]
//
// --implicit writes the same tiles as implicit tiling (subtree files; tileset.json is one tile).
// --features makes the city's buildings features (class `building`: id, height, floors, use) that the tiles carry,
// so that a pick on the tiles names the building; without it the city is the benchmarks' (docs/scenes.md).
// --points writes a scan as an octree of point tiles (sg::buildPointTiles), out of core; --pnts makes them .pnts
// for 3D Tiles 1.0 readers. --shard I/N builds the I-th of N shares of it (processes or machines writing to one DIR);
// --merge, once every shard is done, builds the levels above and tileset.json. Prints points, tiles, time, points
// per second and peak resident memory.
//
// Prints what was written. Exit 2, naming the problem, on bad arguments or an unreadable input.
#include "loaders/gltf/Gltf.h"
#include "loaders/points/PointTiler.h"
#include "loaders/points/Scan.h"
#include "loaders/tiles/TilesetWrite.h"
#include "nodes/Transform.h"
#include "testbed/City.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include <sys/resource.h>

namespace {

int usage(const std::string& problem) {
    std::fprintf(stderr,
                 "sgtile: %s\n"
                 "usage: sgtile --city N --out DIR [--max-triangles T] [--proxies exact|simplified] [--implicit] "
                 "[--features]\n"
                 "       sgtile INPUT.glb|.gltf --out DIR [--max-triangles T] [--proxies exact|simplified] "
                 "[--implicit]\n"
                 "       sgtile --points SCAN.las|.ply --out DIR [--pnts] [--max-points-per-tile N] [--shard I/N] "
                 "[--merge]\n",
                 problem.c_str());
    return 2;
}

// A whole positive number, or -1.
long long positive(const char* s) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s, &end, 10);
    return (errno || end == s || *end || v <= 0) ? -1 : v;
}

// "I/N" with 0 <= I < N.
bool parseShard(const std::string& s, int& shard, int& shards) {
    const size_t slash = s.find('/');
    if (slash == std::string::npos) return false;
    const long long n = positive(s.substr(slash + 1).c_str());
    const long long i = s.substr(0, slash) == "0" ? 0 : positive(s.substr(0, slash).c_str());
    if (n < 1 || n > 65536 || i < 0 || i >= n) return false;
    shard = int(i), shards = int(n);
    return true;
}

int tilePoints(int argc, char** argv) {
    std::string scanFile, out;
    sg::PointTileOptions options;
    bool sharded = false, merge = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--points" || a == "--out" || a == "--max-points-per-tile" || a == "--shard") {
            if (!hasValue) return usage(a + " needs a value");
            const std::string v = argv[++i];
            if (a == "--points") scanFile = v;
            if (a == "--out") out = v;
            if (a == "--max-points-per-tile") {
                const long long n = positive(v.c_str());
                if (n < 1) return usage("--max-points-per-tile wants a positive number, not " + v);
                options.maxPointsPerTile = size_t(n);
                options.chunkPoints = std::max(options.chunkPoints, options.maxPointsPerTile);
            }
            if (a == "--shard" && !parseShard(v, options.shard, options.shards))
                return usage("--shard wants I/N with 0 <= I < N, not " + v);
            sharded = sharded || a == "--shard";
        } else if (a == "--pnts") {
            options.pnts = true;
        } else if (a == "--merge") {
            merge = true;
        } else {
            return usage("unknown option for --points: " + a);
        }
    }
    if (scanFile.empty() || out.empty()) return usage("--points FILE and --out DIR are required");
    if (sharded && merge) return usage("--shard and --merge are separate runs");
    options.stage = sharded ? sg::PointTileOptions::Shard
                    : merge ? sg::PointTileOptions::Merge
                            : sg::PointTileOptions::All;
    try {
        const std::unique_ptr<sg::ScanReader> scan = sg::openScan(scanFile);
        const sg::PointTileStats s = sg::buildPointTiles(*scan, out, options);
        struct rusage ru {};
        getrusage(RUSAGE_SELF, &ru);
        std::printf(
            "%s: %llu points, %zu tiles, %d levels, %.1f MB in %.2f s (%.0f points/s), peak resident %.1f MB, largest "
            "chunk %llu points\n",
            out.c_str(), (unsigned long long)s.points, s.tiles, s.levels, s.bytes / 1e6, s.seconds,
            s.seconds > 0 ? double(s.points) / s.seconds : 0.0, ru.ru_maxrss / 1024.0,
            (unsigned long long)s.largestChunk);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgtile: %s\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--points") == 0) return tilePoints(argc, argv);
    std::string input, out;
    long long city = 0;
    bool features = false;
    sg::TileWriteOptions options;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--city" || a == "--out" || a == "--max-triangles" || a == "--proxies") {
            if (!hasValue) return usage(a + " needs a value");
            const char* v = argv[++i];
            if (a == "--city") {
                city = positive(v);
                if (city < 1 || city > 100000)
                    return usage("--city wants a number of cells from 1 to 100000, not " + std::string(v));
            } else if (a == "--out") {
                out = v;
            } else if (a == "--max-triangles") {
                const long long t = positive(v);
                if (t < 1) return usage("--max-triangles wants a positive number, not " + std::string(v));
                options.maxTrianglesPerTile = size_t(t);
            } else if (std::strcmp(v, "exact") == 0) {
                options.proxies = sg::TileWriteOptions::Proxies::Exact;
            } else if (std::strcmp(v, "simplified") == 0) {
                options.proxies = sg::TileWriteOptions::Proxies::Simplified;
            } else {
                return usage("--proxies wants exact or simplified, not " + std::string(v));
            }
        } else if (a == "--implicit") {
            options.implicit = true;
        } else if (a == "--features") {
            features = true;
        } else if (!a.empty() && a[0] == '-') {
            return usage("unknown option " + a);
        } else if (input.empty()) {
            input = a;
        } else {
            return usage("more than one input: " + input + " and " + a);
        }
    }
    if (out.empty()) return usage("--out DIR is required");
    if (city > 0 && !input.empty()) return usage("--city and an input file are alternatives");
    if (city == 0 && input.empty()) return usage("no scene: give --city N or an input file");
    if (features && city == 0) return usage("--features is for --city (a file's features are its own)");
    if (features && city > 65535) return usage("--features wants --city of at most 65535 (a building's id is 32-bit)");

    const auto start = std::chrono::steady_clock::now();
    sg::ref_ptr<sg::Node> scene;
    if (city > 0) {
        scene = scenes::buildCity({int(city), false, features});
    } else {
        try {
            // glTF is +Y up; the tiler wants +Z up (it turns its contents back to +Y).
            auto zUp = sg::make<sg::Transform>(
                sg::dmat4(sg::dvec4(1, 0, 0, 0), sg::dvec4(0, 0, 1, 0), sg::dvec4(0, -1, 0, 0), sg::dvec4(0, 0, 0, 1)));
            zUp->addChild(sg::loadGltf(input).root);
            scene = zUp;
        } catch (const std::exception& e) {
            return usage(std::string("cannot read the input: ") + e.what());
        }
    }
    const double built = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("scene built in %.1f s\n", built);
    options.progress = [last = -1](double f, const std::string& stage) mutable {
        const int pct = int(f * 100);
        if (pct / 10 != last / 10) std::printf("  %3d%% %s\n", pct, stage.c_str()), std::fflush(stdout), last = pct;
    };
    try {
        const sg::TileWriteReport r = sg::writeTileset(*scene, out, options);
        std::printf("%s/tileset.json: %zu tiles, %zu contents, %.1f MB, written in %.1f s\n", out.c_str(), r.tiles,
                    r.contents, r.bytes / 1e6, r.seconds);
        for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgtile: %s\n", e.what());
        return 1;
    }
    return 0;
}
