// sgbench: the benchmarks whose figures docs/benchmarks.md reports. `sgbench <command> [--options] [--json]`.
#include "sgbench/Bench.h"

#include <malloc.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>

namespace bench {

Args parseArgs(int argc, char** argv) {
    Args a;
    if (argc > 1) a.command = argv[1];
    for (int i = 2; i < argc; ++i) {
        std::string k = argv[i];
        if (k.rfind("--", 0) != 0) throw std::invalid_argument("sgbench: unexpected argument '" + k + "'");
        k = k.substr(2);
        if (i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0)
            a.opts[k] = argv[++i];
        else
            a.opts[k] = "1";
    }
    return a;
}

std::string Args::str(const std::string& k, const std::string& def) const {
    auto it = opts.find(k);
    return it == opts.end() ? def : it->second;
}

long Args::num(const std::string& k, long def) const {
    auto it = opts.find(k);
    if (it == opts.end()) return def;
    char* end = nullptr;
    const long v = std::strtol(it->second.c_str(), &end, 10);
    if (!end || *end)
        throw std::invalid_argument("sgbench: --" + k + " needs a whole number, got '" + it->second + "'");
    return v;
}

Json& Json::add(const std::string& k, double v) {
    char buf[64];
    if (std::isfinite(v))
        std::snprintf(buf, sizeof buf, "%.6g", v);
    else
        std::snprintf(buf, sizeof buf, "null");
    kv_.emplace_back(k, buf);
    return *this;
}
Json& Json::add(const std::string& k, const std::string& v) {
    kv_.emplace_back(k, "\"" + v + "\"");
    return *this;
}
Json& Json::addInt(const std::string& k, long long v) {
    kv_.emplace_back(k, std::to_string(v));
    return *this;
}
std::string Json::str() const {
    std::string s = "{";
    for (size_t i = 0; i < kv_.size(); ++i) s += (i ? ", \"" : "\"") + kv_[i].first + "\": " + kv_[i].second;
    return s + "}";
}
std::string Json::table() const {
    size_t w = 0;
    for (auto& p : kv_) w = std::max(w, p.first.size());
    std::string s;
    for (auto& p : kv_) s += "  " + p.first + std::string(w - p.first.size() + 2, ' ') + p.second + "\n";
    return s;
}

void Json::print(const Args& a) const {
    if (a.flag("json"))
        std::cout << str() << std::endl;
    else
        std::cout << "sgbench " << a.command << "\n" << table();
}

double rssMb() {
    std::ifstream f("/proc/self/statm");
    long pages = 0, rss = 0;
    f >> pages >> rss;
    return double(rss) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double heapMb() {
    const struct mallinfo2 m = mallinfo2();
    return double(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}

}  // namespace bench

static void usage() {
    std::fprintf(
        stderr,
        "usage: sgbench cull --scene city --n N [--strategy S] [--path orbit|street] [--json]\n"
        "       sgbench accuracy --scene city|random|office|FILE.gltf --views K --strategy S [--seed X] [--n N | --r "
        "R]\n"
        "                [--occlusion off|every-frame|adaptive] [--cap front|centre] [--width W --height H] [--json]\n"
        "       sgbench occlusion --scene city|office [--n N | --r R] [--path street|orbit|walk] [--occlusion "
        "every-frame|adaptive]\n"
        "                [--cap front|centre] [--max-occluders K] [--min-pixels P] [--splits S] [--every K] "
        "[--no-draw] [--json]\n"
        "                [--method tree|hom|hom-approx|pvs|pvs+tree|pvs+hom|pvs+hom-approx] [--hom-opacity PERCENT] "
        "[--hom-size N]\n"
        "                [--obb-levels L] [--cell-size M] [--pvs-occluders K] [--pixels]\n"
        "                [--occluders authored|generated] [--gltf FILE.glb | --tileset DIR/tileset.json]\n"
        "       sgbench lod --scene city|factory [--n N] [--path orbit|street] --budget-ms B --method "
        "static|stress|budget "
        "[--no-drop] [--guess-accuracy] [--same-view] [--every K]\n"
        "                [--background-load none|spin] [--jitter-draws 60] [--depth classic|reverse-z]\n"
        "                [--keep-over-pct P --keep-under-pct P] [--json]\n"
        "       sgbench pick --scene city [--n N] [--rays-per-frame K] [--steps S] [--agreement-views V] [--json]\n"
        "       sgbench pick --features [--n 316] [--rays-per-frame K] [--rounds R] [--json]\n"
        "       sgbench load [--size-mb 100] [--runs 5] [--file PATH.glb] [--json]\n"
        "       sgbench load --features [--count 100000] [--runs 5] [--dir /tmp] [--json]\n"
        "       sgbench pvs [--scene city|office|both] [--n N] [--r R] [--sweep cells|occluders|both] [--cell-size M]\n"
        "                [--max-occluders K] [--resolution P] [--json]\n"
        "       sgbench terrain [--sizes 1025,2049,4097] [--fov 60,90,120] [--frames 5] [--reps 100] [--tile 33]\n"
        "                [--spacing 10] [--seed 2002] [--no-draw] [--json]\n"
        "       sgbench terrain --occluders [--sizes 1025] [--views 24] [--reps 5] [--blocks 2] [--height 20]\n"
        "                [--tile 33] [--spacing 10] [--seed 2002]\n"
        "       sgbench pcvr [--frames N] [--clusters K1,K2,...] [--seed S] [--no-pixels] [--json]\n"
        "       sgbench pareto [--quick] [--scenes city-orbit,city-street,office,factory,terrain,pcvr-city] [--out "
        "DIR] [--views K]\n"
        "                [--rounds R] [--methods M1,M2] [--n N] [--r R] [--width W --height H] [--budget-ms B]\n"
        "                [--strict-reference] [--tolerance PERCENT]\n"
        "       sgbench depth [--n N] [--rounds R] [--json]\n"
        "       sgbench tiles --tileset PATH|URL [--n N] [--path orbit|low|teleport [--views K]] [--frames F]\n"
        "                [--width W --height H] [--fps F] [--keep-freed-memory 0|1] [--share-meshes 0|1]\n"
        "                [--loaders K] [--loader-nice V] [--resident-mb M] [--baseline] [--csv FILE] [--json]\n"
        "                [--point-size PX] [--round] [--edl] [--header H] [--ca-file CA.pem] [--cache FILE]\n"
        "       sgbench tiles --tileset PATH|URL --path loads [--loads K] [--runs R] [--parse-dir DIR] [--json]\n"
        "       sgbench tiles --tileset SCAN_TILES/tileset.json --path factory-walk [--frames F] [--settle-check\n"
        "                [--views K] [--png PREFIX]] [--point-size PX] [--round] [--edl] [--width W --height H] "
        "[--json]\n"
        "       sgbench frame [--scene city|factory] [--n N] [--path orbit|street|walk] [--threading "
        "draw|cull-per-view|app-cull-draw]\n"
        "                [--frames F] [--rounds R] [--views 1|2] [--lod static|stress|budget] [--budget-ms B]\n"
        "                [--collide none|sync|async] [--app-ms MS] [--cull-only] [--width W --height H] [--json]\n"
        "       sgbench style [--n 100] [--frames F] [--restyles K] [--width W --height H] [--json]\n"
        "       sgbench points [--count N] [--frames F] [--width W --height H] [--json]\n"
        "       sgbench motion [--figures N] [--moving K] [--n CITY] [--frames F] [--draw 0|1] [--width W --height H]\n"
        "                      [--json]\n"
        "       sgbench variants [--width W --height H] [--json]\n"
        "strategies: none sphere aabb (default) sphere-sphere center-box; --small-feature PIXELS adds small-feature "
        "culling\n");
}

int main(int argc, char** argv) {
    try {
        const bench::Args a = bench::parseArgs(argc, argv);
        if (a.command == "cull") return bench::runCull(a);
        if (a.command == "accuracy") return bench::runAccuracy(a);
        if (a.command == "occlusion") return bench::runOcclusion(a);
        if (a.command == "lod") return bench::runLod(a);
        if (a.command == "pick") return bench::runPick(a);
        if (a.command == "load") return bench::runLoad(a);
        if (a.command == "pvs") return bench::runPvs(a);
        if (a.command == "terrain") return bench::runTerrain(a);
        if (a.command == "pcvr") return bench::runPcvr(a);
        if (a.command == "pareto") return bench::runPareto(a);
        if (a.command == "tiles") return bench::runTiles(a);
        if (a.command == "frame") return bench::runFrame(a);
        if (a.command == "depth") return bench::runDepth(a);
        if (a.command == "style") return bench::runStyle(a);
        if (a.command == "points") return bench::runPoints(a);
        if (a.command == "motion") return bench::runMotion(a);
        if (a.command == "variants") return bench::runVariants(a);
        usage();
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
