// sgbench tiles --path loads: the tileset's load function timed alone, tile after tile on one thread, against the
// glTF loader's parse of the tileset's own content files (sg::loadGltf from memory, as `sgbench load` times it),
// both in milliseconds per MB of content read. What the load adds to the parse (sharing equal meshes, the
// closed-mesh test, the tile's nodes, occluders when asked) is the difference.
#include "loaders/gltf/Gltf.h"
#include "loaders/tiles/Tileset.h"
#include "nodes/Group.h"
#include "nodes/PagedLOD.h"
#include "sgbench/Bench.h"
#include "sgbench/Tiles.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

void findPaged(sg::Node& n, std::deque<sg::PageSource>& out) {
    if (auto* p = dynamic_cast<sg::PagedLOD*>(&n)) out.push_back({p->file(), p->part()});
    if (auto* g = dynamic_cast<sg::Group*>(&n))
        for (size_t i = 0; i < g->numChildren(); ++i) findPaged(*g->child(i), out);
}

// The tileset's .glb files in name order until `bytes`, each parsed from memory `runs` times: ms per MB (median of
// the runs' totals).
double parseMsPerMb(const std::string& dir, uint64_t bytes, long runs, uint64_t& parsed) {
    namespace fs = std::filesystem;
    std::vector<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && e.path().extension() == ".glb") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    std::vector<std::vector<unsigned char>> held;
    parsed = 0;
    for (const std::string& f : files) {
        if (parsed >= bytes) break;
        std::ifstream in(f, std::ios::binary);
        held.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        parsed += held.back().size();
    }
    if (held.empty()) throw std::invalid_argument("sgbench tiles --path loads: no .glb under " + dir);
    std::vector<double> totals;
    for (long r = 0; r < runs; ++r) {
        const auto t0 = Clock::now();
        for (const std::vector<unsigned char>& b : held) sg::loadGltfFromMemory("tile.glb", b.data(), b.size());
        totals.push_back(msSince(t0));
    }
    return median(totals) / (double(parsed) / (1 << 20));
}

}  // namespace

int measureTileLoads(const Args& a, const std::string& file, const sg::TilesetOptions& options) {
    const long loads = a.num("loads", 100), runs = a.num("runs", 3);
    if (loads < 1 || runs < 1) throw std::invalid_argument("sgbench tiles --path loads: --loads and --runs >= 1");
    const sg::ResourceCounters& counters = *options.resource.counters;
    const sg::Tileset ts = sg::loadTileset(file, options);
    const sg::PageLoadFunction load = ts.loadFunction();
    std::deque<sg::PageSource> queue;
    findPaged(*ts.root(), queue);
    const uint64_t bytes0 = counters.bytes;
    std::vector<double> ms;
    double total = 0.0;
    while (!queue.empty() && long(ms.size()) < loads) {
        const sg::PageSource s = queue.front();
        queue.pop_front();
        const auto t0 = Clock::now();
        sg::ref_ptr<sg::Node> detail = load(s);
        ms.push_back(msSince(t0));
        total += ms.back();
        findPaged(*detail, queue);  // breadth first: the coarse tiles, then their children's
    }
    const uint64_t bytes = counters.bytes - bytes0;
    uint64_t parsedBytes = 0;
    // A tileset read over http(s) names the directory it is served from (--parse-dir) for the parse's files.
    const std::string dir =
        a.str("parse-dir", sg::isUrl(file) ? "" : std::filesystem::path(file).parent_path().string());
    if (dir.empty()) throw std::invalid_argument("sgbench tiles --path loads: a URL needs --parse-dir DIR");
    const double parse = parseMsPerMb(dir, bytes, runs, parsedBytes);
    const double loadRate = total / (double(bytes) / (1 << 20));
    Json j;
    j.add("command", "tiles").add("tileset", file).add("path", "loads").addInt("loads", long(ms.size()));
    j.add("content_mb", double(bytes) / (1 << 20)).add("load_ms_total", total).add("load_ms_median", median(ms));
    j.add("load_ms_per_mb", loadRate).add("parse_mb", double(parsedBytes) / (1 << 20));
    j.add("parse_ms_per_mb", parse).add("ratio", loadRate / parse);
    j.addInt("meshes_shared", long(ts.counts().sharedMeshes));
    j.print(a);
    return 0;
}

}  // namespace bench
