// writeTileset: the scene's units placed in a quadtree over its x/y extent, each tile's content built on this
// thread and saved (saveGltf) by a pool of threads in batches, then tileset.json (or, as implicit tiling, the
// subtree files and a tileset.json of one tile: TilesetWriteImplicit.cpp).
//
// Why an exact inner tile draws what the graph draws. A tile's refinement distance D is the largest reach of the
// finest child of the distance LODs below it; its content keeps, in every such LOD, the children that reach
// beyond D (with their ranges: the LOD still switches between them), and its geometric error is
// maxSSE * D / K. A reader with the reference view refines the tile when the eye is nearer than D to the tile's
// bounding volume, so the content shows only with the eye at least D from the volume, and then at least D from
// every point inside it: from every LOD centre, which the box holds (TilesetContent.cpp's bound). There the
// graph would show no dropped child (each stops at or before D) and shows the kept ones exactly as the copy does.
// Nearer than D the children are drawn, down to the leaves, which hold their units whole.
#include "loaders/tiles/TilesetWrite.h"

#include "loaders/gltf/Gltf.h"
#include "loaders/tiles/internal/TilesetDetail.h"
#include "nodes/Transform.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace sg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using tiles::Proxy;
using tiles::Unit;

constexpr int kMaxDepth = 30;  // units at one point never separate: a leaf over the limit then (warned)

// glTF is +Y up; the 3D Tiles reader turns it to +Z up: the content is written turned the other way,
// (x, y, z) -> (x, z, -y).
const dmat4 kZupToYup(dvec4(1, 0, 0, 0), dvec4(0, 0, -1, 0), dvec4(0, 1, 0, 0), dvec4(0, 0, 0, 1));

struct Rect {
    glm::dvec2 min, max;
};

// A tile's content waiting to be saved.
struct Pending {
    ref_ptr<Node> graph;
    std::string path;
    uint64_t triangles = 0;
};

class TileWriter {
public:
    TileWriter(const Node& root, const std::string& dir, const TileWriteOptions& o) : options_(o), dir_(dir) {
        const double k = o.referenceHeightPixels / (2.0 * std::tan(glm::radians(o.referenceFovYDegrees) / 2.0));
        errorPerMetre_ = o.maximumScreenSpaceError / k;
        stage("collecting units", 0.0);
        // A unit small against a tile, so that the quadtree can fill its leaves.
        units_ = tiles::collectUnits(root, std::max<uint64_t>(1, o.maxTrianglesPerTile / 8));
        for (const Unit& u : units_.units) sceneBox_.expand(u.box);
        order_.resize(units_.units.size());
        for (size_t i = 0; i < order_.size(); ++i) order_[i] = uint32_t(i);
        threads_ = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
    }

    json write(TileWriteReport& report) {
        report_ = &report;
        if (sceneBox_.empty()) {
            report.warnings.push_back("the scene draws nothing: the tileset holds one empty tile");
            sceneBox_ = Box{dvec3(0.0), dvec3(0.0)};
        }
        // Every box grows by the same small margin: the float contents stay inside, and children inside parents.
        pad_ = 1e-6 * std::max(1.0, glm::length(sceneBox_.max - sceneBox_.min));
        const Rect rect{glm::dvec2(sceneBox_.min), glm::dvec2(sceneBox_.max)};
        Built root = tile(0, order_.size(), rect, 0, 0, 0, dvec3(0.0));
        flush();
        json tileset;
        tileset["asset"] = {{"version", "1.1"}, {"generator", "sgkit writeTileset"}};
        // The error if the tileset is not drawn at all: above the root's, as the specification requires.
        tileset["geometricError"] = std::max(root.error * 2.0, errorPerMetre_ * options_.farDistance);
        if (options_.implicit) {
            json schema;
            tileset["root"] = tiles::writeImplicitTiles(implicitTiles_, rootCentre_, dir_, schema, report.bytes);
            tileset["schema"] = std::move(schema);
        } else {
            tileset["root"] = std::move(root.tile);
        }
        return tileset;
    }

private:
    struct Built {
        json tile;
        double error = 0.0;
        Proxy proxy;  // Simplified only: what the parent merges
    };
    // What the units of a tile hold together: their box, triangles and largest reach.
    struct Extent {
        Box box;
        uint64_t triangles = 0;
        double reach = 0.0;
    };
    // What an inner tile's children hand up: their largest error and (Simplified only) their proxies.
    struct ChildrenBuilt {
        double error = 0.0;
        std::vector<Proxy> proxies;
    };
    // A tile's content before it is queued: the graph (turned to +Y up), whether it draws, its triangles.
    struct Content {
        ref_ptr<Transform> graph;
        bool present = false;
        uint64_t triangles = 0;
    };

    void stage(const std::string& what, double fraction) {
        if (options_.progress) options_.progress(fraction, what);
    }

    const Unit& unit(size_t i) const { return units_.units[order_[i]]; }

    // The tile of units order_[b, e) in `rect`, at quadtree `level` and position (x, y); `parentCentre` is the
    // parent tile's frame.
    Built tile(size_t b, size_t e, const Rect& rect, int level, uint64_t x, uint64_t y, const dvec3& parentCentre) {
        const Extent extent = extentOf(b, e, rect);
        const dvec3 centre = extent.box.center();
        if (level == 0) rootCentre_ = centre;
        const bool leaf = isLeaf(b, e, extent.triangles, level, x, y);

        Built out;
        ChildrenBuilt children;
        if (!leaf) children = buildChildren(b, e, rect, level, x, y, centre, out);

        // The content and the error.
        Content content{make<Transform>(kZupToYup)};
        const dmat4 toTile = glm::translate(dmat4(1.0), -centre);
        if (leaf)
            leafContent(b, e, extent.triangles, centre, toTile, content, out);
        else if (options_.proxies == TileWriteOptions::Proxies::Exact)
            exactContent(b, e, extent.reach, toTile, children.error, content, out);
        else
            simplifiedContent(children, centre, content, out);

        const dvec3 half = extent.box.halfExtent() + dvec3(pad_);
        if (content.present && options_.instancing) tiles::instanceRepeats(*content.graph);
        if (options_.implicit)
            placeImplicit(level, x, y, centre, half, out.error, content);
        else
            describeExplicit(level, x, y, centre - parentCentre, half, content, out);
        ++report_->tiles;
        if (leaf) {
            unitsDone_ += e - b;
            stage("writing tiles", double(unitsDone_) / double(std::max<size_t>(1, order_.size())));
        }
        return out;
    }

    // What the units order_[b, e) hold together; an empty box becomes the rect's, flat.
    Extent extentOf(size_t b, size_t e, const Rect& rect) const {
        Extent out;
        for (size_t i = b; i < e; ++i) {
            out.box.expand(unit(i).box);
            out.triangles += unit(i).triangles;
            out.reach = std::max(out.reach, unit(i).reach);
        }
        if (out.box.empty()) out.box = Box{dvec3(rect.min, 0.0), dvec3(rect.max, 0.0)};
        return out;
    }

    // A leaf holds few enough triangles, a single unit, or is as deep as the quadtree goes (warned: its units
    // do not separate).
    bool isLeaf(size_t b, size_t e, uint64_t triangles, int level, uint64_t x, uint64_t y) {
        const bool leaf = triangles <= options_.maxTrianglesPerTile || e - b <= 1 || level >= kMaxDepth;
        if (leaf && triangles > options_.maxTrianglesPerTile && e - b > 1)
            report_->warnings.push_back("tile " + name(level, x, y) + " holds " + std::to_string(triangles) +
                                        " triangles: its units do not separate");
        return leaf;
    }

    // The child tiles of an inner tile, written depth first; their JSON goes into out.tile (explicit tiling).
    ChildrenBuilt buildChildren(size_t b, size_t e, const Rect& rect, int level, uint64_t x, uint64_t y,
                                const dvec3& centre, Built& out) {
        ChildrenBuilt built;
        // Quadrants by unit centre; empty ones get no tile.
        const glm::dvec2 mid = (rect.min + rect.max) * 0.5;
        auto cx = [&](uint32_t u) { return units_.units[u].box.empty() ? mid.x : units_.units[u].box.center().x; };
        auto cy = [&](uint32_t u) { return units_.units[u].box.empty() ? mid.y : units_.units[u].box.center().y; };
        const auto first = order_.begin() + std::ptrdiff_t(b), last = order_.begin() + std::ptrdiff_t(e);
        const auto xs = std::partition(first, last, [&](uint32_t u) { return cx(u) < mid.x; });
        const auto y0 = std::partition(first, xs, [&](uint32_t u) { return cy(u) < mid.y; });
        const auto y1 = std::partition(xs, last, [&](uint32_t u) { return cy(u) < mid.y; });
        const decltype(first) cuts[5] = {first, y0, xs, y1, last};
        json children = json::array();
        for (int q = 0; q < 4; ++q) {
            if (cuts[q] == cuts[q + 1]) continue;
            const int qx = q / 2, qy = q % 2;
            const Rect r{glm::dvec2(qx ? mid.x : rect.min.x, qy ? mid.y : rect.min.y),
                         glm::dvec2(qx ? rect.max.x : mid.x, qy ? rect.max.y : mid.y)};
            Built c = tile(size_t(cuts[q] - order_.begin()), size_t(cuts[q + 1] - order_.begin()), r, level + 1,
                           x * 2 + uint64_t(qx), y * 2 + uint64_t(qy), centre);
            built.error = std::max(built.error, c.error);
            children.push_back(std::move(c.tile));
            if (options_.proxies == TileWriteOptions::Proxies::Simplified) built.proxies.push_back(std::move(c.proxy));
        }
        if (!options_.implicit) out.tile["children"] = std::move(children);
        return built;
    }

    // A leaf's content: its units whole; its error 0.
    void leafContent(size_t b, size_t e, uint64_t triangles, const dvec3& centre, const dmat4& toTile, Content& content,
                     Built& out) {
        for (size_t i = b; i < e; ++i)
            tiles::addUnit(*content.graph, *unit(i).node, units_.matrices[unit(i).above], toTile, tiles::kKeepAll);
        content.present = e > b;
        content.triangles = triangles;
        out.error = 0.0;
        if (options_.proxies == TileWriteOptions::Proxies::Simplified) {
            out.proxy.centre = centre;
            for (size_t i = b; i < e; ++i)
                tiles::addFinest(out.proxy, *unit(i).node, units_.matrices[unit(i).above], billboardsSkipped_);
        }
    }

    // An inner tile's exact content: its units with their distance LODs reduced at `reach`.
    void exactContent(size_t b, size_t e, double reach, const dmat4& toTile, double childError, Content& content,
                      Built& out) {
        // No content where no exact reduction exists (no distance LOD, or one reaching beyond the far
        // distance) or where it would exceed the limit: the tile then refines wherever it can be seen.
        const uint64_t limit = options_.maxTrianglesPerTile;
        if (reach > 0.0 && reach < options_.farDistance) {
            for (size_t i = b; i < e && content.triangles <= limit; ++i)
                content.triangles += tiles::reducedTriangles(*unit(i).node, reach, limit - content.triangles);
            content.present = content.triangles <= limit;
        }
        if (content.present)
            for (size_t i = b; i < e; ++i)
                tiles::addUnit(*content.graph, *unit(i).node, units_.matrices[unit(i).above], toTile, reach);
        out.error = std::max(childError, errorPerMetre_ * (content.present ? reach : options_.farDistance));
    }

    // An inner tile's simplified content: its children's proxies merged and simplified to half their triangles.
    void simplifiedContent(const ChildrenBuilt& children, const dvec3& centre, Content& content, Built& out) {
        uint64_t merged = 0;
        for (const Proxy& p : children.proxies) merged += p.triangles();
        out.proxy = tiles::simplifyMerged(children.proxies, centre,
                                          std::min<uint64_t>(merged / 2, options_.maxTrianglesPerTile));
        tiles::addProxy(*content.graph, out.proxy);
        content.triangles = out.proxy.triangles();
        content.present = content.triangles > 0;
        out.error = std::max(children.error, out.proxy.error);
    }

    // Implicit tiling: the tile recorded for the subtree files, its content queued as tiles/{level}/{x}/{y}.glb.
    void placeImplicit(int level, uint64_t x, uint64_t y, const dvec3& centre, const dvec3& half, double error,
                       const Content& content) {
        implicitTiles_.push_back({uint32_t(level), x, y, centre, half, error, content.present});
        if (!content.present) return;
        // No per-tile transforms in implicit tiling: the content's root node holds its offset from the
        // root's centre (glTF's doubles), the rest of it stays small and relative to its own centre.
        auto placed = make<Transform>(glm::translate(dmat4(1.0), dvec3(kZupToYup * dvec4(centre - rootCentre_, 0.0))));
        placed->addChild(content.graph);
        const std::string folder = dir_ + "/tiles/" + std::to_string(level) + "/" + std::to_string(x);
        std::error_code ec;
        fs::create_directories(folder, ec);
        if (ec) throw std::runtime_error("writeTileset(): " + folder + ": cannot be created: " + ec.message());
        queue(Pending{placed, folder + "/" + std::to_string(y) + ".glb", content.triangles});
    }

    // Explicit tiling: the tile's JSON in out.tile, its content queued as tiles/{level}_{x}_{y}.glb. `shift`: the
    // tile's centre in its parent's frame.
    void describeExplicit(int level, uint64_t x, uint64_t y, const dvec3& shift, const dvec3& half,
                          const Content& content, Built& out) {
        json& t = out.tile;
        t["boundingVolume"]["box"] = {0, 0, 0, half.x, 0, 0, 0, half.y, 0, 0, 0, half.z};
        // 3D Tiles transforms are relative to the parent's frame.
        t["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, shift.x, shift.y, shift.z, 1};
        t["geometricError"] = out.error;
        t["refine"] = "REPLACE";
        if (content.present) {
            const std::string uri = "tiles/" + name(level, x, y) + ".glb";
            t["content"]["uri"] = uri;
            queue(Pending{content.graph, dir_ + "/" + uri, content.triangles});
        }
    }

    static std::string name(int level, uint64_t x, uint64_t y) {
        return std::to_string(level) + "_" + std::to_string(x) + "_" + std::to_string(y);
    }

    // Contents are saved in batches, by several threads: building a content only reads the scene and makes new
    // nodes, but they reference scene nodes (whose parent lists change), so the graphs are made and freed here,
    // between batches.
    void queue(Pending p) {
        batchTriangles_ += p.triangles;
        batch_.push_back(std::move(p));
        if (batch_.size() >= 4 * threads_ || batchTriangles_ >= 8 * options_.maxTrianglesPerTile) flush();
    }

    void flush() {
        std::atomic<size_t> next{0};
        std::mutex failed;
        std::exception_ptr error;
        auto work = [&] {
            for (size_t i; (i = next++) < batch_.size();) {
                try {
                    saveGltf(*batch_[i].graph, batch_[i].path);
                } catch (...) {
                    std::lock_guard<std::mutex> lock(failed);
                    if (!error) error = std::current_exception();
                }
            }
        };
        std::vector<std::thread> pool;
        for (size_t i = 1; i < std::min<size_t>(threads_, batch_.size()); ++i) pool.emplace_back(work);
        work();
        for (auto& t : pool) t.join();
        if (error) std::rethrow_exception(error);
        for (const Pending& p : batch_) {
            report_->bytes += size_t(fs::file_size(p.path));
            ++report_->contents;
        }
        batch_.clear();
        batchTriangles_ = 0;
    }

    const TileWriteOptions& options_;
    std::string dir_;
    double errorPerMetre_ = 0.0, pad_ = 0.0;
    tiles::Units units_;
    std::vector<uint32_t> order_;
    Box sceneBox_;
    TileWriteReport* report_ = nullptr;
    size_t unitsDone_ = 0, billboardsSkipped_ = 0;
    unsigned threads_ = 1;
    std::vector<Pending> batch_;
    uint64_t batchTriangles_ = 0;
    dvec3 rootCentre_{0.0};
    std::vector<tiles::ImplicitTile> implicitTiles_;

public:
    size_t billboardsSkipped() const { return billboardsSkipped_; }
};

void check(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("writeTileset(): " + what);
}

}  // namespace

TileWriteReport writeTileset(const Node& root, const std::string& dir, const TileWriteOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    check(options.maxTrianglesPerTile > 0, "maxTrianglesPerTile must be positive");
    check(
        std::isfinite(options.maximumScreenSpaceError) && options.maximumScreenSpaceError > 0,
        "maximumScreenSpaceError must be positive and finite, not " + std::to_string(options.maximumScreenSpaceError));
    check(options.referenceHeightPixels > 0,
          "referenceHeightPixels must be positive, not " + std::to_string(options.referenceHeightPixels));
    check(options.referenceFovYDegrees > 0 && options.referenceFovYDegrees < 180,
          "referenceFovYDegrees must lie in (0, 180), not " + std::to_string(options.referenceFovYDegrees));
    check(std::isfinite(options.farDistance) && options.farDistance > 0,
          "farDistance must be positive and finite, not " + std::to_string(options.farDistance));
    std::error_code ec;
    fs::create_directories(fs::path(dir) / "tiles", ec);
    if (ec) throw std::runtime_error("writeTileset(): " + dir + ": cannot create the directory: " + ec.message());

    TileWriteReport report;
    TileWriter writer(root, dir, options);
    const json tileset = writer.write(report);
    if (writer.billboardsSkipped())
        report.warnings.push_back(std::to_string(writer.billboardsSkipped()) +
                                  " billboards are left out of the simplified proxies");
    const std::string path = dir + "/tileset.json";
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("writeTileset(): " + path + ": cannot be opened for writing");
    out << tileset.dump();
    out.close();
    if (!out) throw std::runtime_error("writeTileset(): " + path + ": cannot be written");
    report.bytes += size_t(fs::file_size(path));
    if (options.progress) options.progress(1.0, "done");
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace sg
