// Tiles into nodes: a tile is its Transform, its content and, when it has children, a PagedLOD refined by
// screen-space error whose detail is the children's graphs, read in one load. The PagedLOD shows its coarse
// children (a REPLACE tile's content) until the whole detail is attached, so no tile leaves a hole; an ADD tile's
// content sits beside the PagedLOD and stays.
#include "loaders/gltf/internal/GltfDetail.h"
#include "loaders/tiles/internal/BatchTable.h"
#include "loaders/tiles/internal/Pnts.h"
#include "loaders/tiles/internal/TileFormats.h"
#include "loaders/tiles/internal/TilesetTable.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Transform.h"
#include "sg/build/GeneratedOccluders.h"
#include "sg/core/Features.h"
#include "sg/core/NodeVisitor.h"
#include "sg/scene/internal/DistinctGeometries.h"

#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <unordered_set>

namespace sg {
namespace tiles {
namespace {

// A glTF (binary, or JSON from a file so that its external buffers are found) turned +Z up. One read over the
// network or from a data: URI is parsed from memory, where no external file is read.
ref_ptr<Node> gltfContent(const std::shared_ptr<TilesetState>& s, const std::string& uri, const unsigned char* data,
                          size_t size, bool binary, const dmat4& place, const GltfLoadOptions& options = {}) {
    GltfScene g =
        binary || isUrl(uri) || isDataUri(uri) ? loadGltfFromMemory(uri, data, size, options) : loadGltf(uri, options);
    for (const std::string& w : g.warnings) s->warn(uri + ": " + w);
    auto t = make<Transform>(place * yUpToZUp());
    t->addChild(g.root);
    return t;
}

// A tile's batch table as a property store (null when it has none), its warnings named by the tile's URI.
ref_ptr<const PropertyStore> batchTable(const std::shared_ptr<TilesetState>& s, const std::string& uri, Bytes json,
                                        Bytes binary, uint32_t batchLength) {
    std::vector<std::string> warnings;
    ref_ptr<const PropertyStore> store = readBatchTable(uri, json, binary, batchLength, warnings);
    for (const std::string& w : warnings) s->warn(uri + ": " + w);
    return store;
}

// An i3dm's features: one set of Source::Instance over its batch table, an instance's id its BATCH_ID or its
// index. Null when the tile has neither.
ref_ptr<const MeshFeatures> instanceFeatures(const std::shared_ptr<TilesetState>& s, const std::string& uri,
                                             const I3dm& in) {
    const uint32_t n = uint32_t(in.instances.size());
    ref_ptr<const PropertyStore> store = batchTable(s, uri, in.batchJson, in.batchBinary, n);
    if (!store && in.batchIds.empty()) return nullptr;
    FeatureIdSet set;
    set.source = FeatureIdSet::Source::Instance;
    set.propertyTable = store ? 0 : -1;
    set.ids = in.batchIds;
    if (set.ids.empty())
        for (uint32_t i = 0; i < n; ++i) set.ids.push_back(i);
    uint64_t count = 0;
    for (uint32_t id : set.ids) count = std::max(count, uint64_t(id) + 1);
    set.featureCount = uint32_t(std::min<uint64_t>(count, UINT32_MAX));
    if (store && count > n)
        s->warn(uri + ": featureTable.BATCH_ID: ids up to " + std::to_string(count - 1) + " past the batch table's " +
                std::to_string(n) + " rows read as no properties");
    auto f = make<MeshFeatures>();
    f->sets.push_back(std::move(set));
    f->store = store;
    return f;
}

// The point meshes of a tile's content (pnts, or glTF POINTS) get the tile's geometric error as their spacing, as
// CesiumJS attenuates point sizes by it: the error is how far the tile's points may stand from the full detail, so
// points that size close the gaps between them. A tile of error 0 (a leaf) takes CesiumJS' stand-in, the cube root
// of its bounding sphere's volume per point. The points are counted in the tileset's stats.
ref_ptr<Node> spaced(const std::shared_ptr<TilesetState>& s, uint32_t tile, ref_ptr<Node> content) {
    if (!content) return content;
    const TileDesc d = s->tile(tile);
    const double volume = 4.0 / 3.0 * 3.14159265358979323846 * d.sphere.radius * d.sphere.radius * d.sphere.radius;
    size_t points = 0;
    forEachDistinctGeometry(*content, [&](const Geometry& g) {
        Mesh* m = g.mesh();
        if (!m || m->primitive() != Primitive::Points || m->pointCount() == 0) return;
        points += m->pointCount();
        const double spacing = d.geometricError > 0.0 ? d.geometricError : std::cbrt(volume / m->pointCount());
        m->setPointSpacing(float(spacing));  // 0 or not finite: unknown
    });
    if (points > 0) s->countPoints(points);
    return content;
}

ref_ptr<Node> fromBytes(const std::shared_ptr<TilesetState>& s, uint32_t tile, const std::string& uri,
                        const unsigned char* data, size_t size, const dmat4& world, LoadPass& pass) {
    switch (sniffContent(data, size)) {
        case ContentKind::Glb: return spaced(s, tile, gltfContent(s, uri, data, size, true, dmat4(1.0)));
        case ContentKind::B3dm: {
            const B3dm b = parseB3dm(uri, data, size);
            const dmat4 rtc = b.hasRtcCenter ? glm::translate(dmat4(1.0), b.rtcCenter) : dmat4(1.0);
            GltfLoadOptions options;  // the glb's _BATCHID attributes become feature ids into the batch table
            options.batchTable = batchTable(s, uri, b.batchJson, b.batchBinary, b.batchLength);
            return spaced(s, tile, gltfContent(s, uri, b.glb.data, b.glb.size, true, rtc, options));
        }
        case ContentKind::I3dm: {
            const I3dm in = parseI3dm(uri, data, size);
            ref_ptr<Node> proto;
            if (in.glbUri.empty()) {
                proto = gltfContent(s, uri, in.glb.data, in.glb.size, true, dmat4(1.0));
            } else {
                const std::string model = resolveReference(uri, in.glbUri);
                const std::vector<unsigned char> bytes = readResource(model, s->options.resource);
                proto = gltfContent(s, model, bytes.data(), bytes.size(),
                                    sniffContent(bytes.data(), bytes.size()) == ContentKind::Glb, dmat4(1.0));
            }
            const ref_ptr<const MeshFeatures> features = instanceFeatures(s, uri, in);
            auto g = make<Group>();
            for (uint32_t k = 0; k < uint32_t(in.instances.size()); ++k) {
                auto instance = make<Instance>(proto, in.instances[k]);
                if (features) instance->setFeatures(features, k);
                g->addChild(instance);
            }
            return spaced(s, tile, g);
        }
        case ContentKind::Cmpt: {
            const Cmpt c = parseCmpt(uri, data, size);
            auto g = make<Group>();
            for (size_t i = 0; i < c.tiles.size(); ++i) {
                ref_ptr<Node> n = fromBytes(s, tile, uri + "#tiles[" + std::to_string(i) + "]", c.tiles[i].data,
                                            c.tiles[i].size, world, pass);
                if (n) g->addChild(n);
            }
            return g;
        }
        case ContentKind::Pnts: {  // +Z up already: no glTF axis change, only its RTC_CENTER
            std::vector<std::string> warnings;
            ref_ptr<Node> n = readPnts(uri, data, size, warnings);
            for (const std::string& w : warnings) s->warn(uri + ": " + w);
            return spaced(s, tile, n);
        }
        case ContentKind::Json: {
            bool tileset = false;
            try {
                const auto j = nlohmann::json::parse(data, data + size);
                tileset = j.is_object() && j.contains("root");
            } catch (const nlohmann::json::exception&) {
            }
            if (!tileset) return spaced(s, tile, gltfContent(s, uri, data, size, false, dmat4(1.0)));
            const TileDesc d = s->tile(tile);
            const uint32_t root = s->addTileset(uri, std::vector<unsigned char>(data, data + size), d.source, tile);
            return buildTile(s, root, world, false, pass);
        }
        case ContentKind::Unknown: break;
    }
    std::string magic;
    for (size_t i = 0; i < std::min<size_t>(size, 4); ++i) magic += std::isprint(data[i]) ? char(data[i]) : '?';
    throw LoadError(uri, "",
                    "not a tile content (glb, b3dm, i3dm, cmpt, pnts or JSON): it starts with '" + magic + "'");
}

// A volume in the tile's frame: an Earth-centred one (a region's) brought into it.
Sphere inFrame(Sphere sp, bool earthCentred, const dmat4& world) {
    if (earthCentred) {
        const dmat4 inv = glm::inverse(world);
        sp.center = dvec3(inv * dvec4(sp.center, 1.0));
        sp.radius *= maxScale(inv);
    }
    return sp;
}

// A tile with a viewerRequestVolume: what it holds below a distance LOD centred on the volume's sphere that
// shows it only with the eye inside, so that it is neither drawn nor refined (nor its children asked for) from
// outside, as the specification says.
ref_ptr<Node> gated(const ref_ptr<Group>& tile, const TileDesc& d, const dmat4& world) {
    if (!d.request) return tile;
    const Sphere v = inFrame(*d.request, d.requestRegion, world);
    auto body = make<Group>();
    while (tile->numChildren() > 0) {
        body->addChild(tile->child(0));
        tile->removeChild(size_t(0));
    }
    auto gate = make<LOD>();
    gate->setCenter(v.center);
    gate->addChild(body, 0.0f, float(v.radius * maxScale(world)));  // an LOD's distances are the graph's
    tile->addChild(gate);
    return tile;
}

}  // namespace

dmat4 yUpToZUp() {
    dmat4 m(1.0);
    m[1] = dvec4(0, 0, 1, 0);   // +Y goes to +Z
    m[2] = dvec4(0, -1, 0, 0);  // +Z goes to -Y
    return m;
}

ref_ptr<Node> loadContent(const std::shared_ptr<TilesetState>& s, uint32_t tile, const std::string& uri,
                          const dmat4& world, LoadPass& pass) {
    const std::vector<unsigned char> bytes = readResource(uri, s->options.resource);
    ref_ptr<Node> n = fromBytes(s, tile, uri, bytes.data(), bytes.size(), world, pass);
    s->contentLoaded(tile, uri);
    return n;
}

ref_ptr<Node> buildTile(const std::shared_ptr<TilesetState>& s, uint32_t t, const dmat4& parentWorld, bool drawnAbove,
                        LoadPass& pass) {
    const TileDesc d = s->resolve(t);
    const dmat4 world = parentWorld * d.transform;
    s->setWorld(t, world);
    if (pass.budget > 0) --pass.budget;
    ref_ptr<Group> g = d.hasTransform ? ref_ptr<Group>(make<Transform>(d.transform)) : make<Group>();
    ref_ptr<Group> content;
    for (size_t i = 0; i < d.contents.size(); ++i) {
        ref_ptr<Node> n;
        try {
            n = loadContent(s, t, d.contents[i], world, pass);
        } catch (const LoadError& e) {
            // A missing or corrupt content leaves the tile empty and the load goes on. One that may pass fails the
            // load, which the pager retries, but only once the rest is read: every such content of the load
            // counts its attempt (TilesetState::contentFailed), so that all of them reach the last one together.
            if (!s->contentFailed(t, d, i, e) && !pass.retry) pass.retry = std::current_exception();
        }
        if (n) {
            if (!content) {  // a TileContent: what a pick finds the tile's metadata by
                auto c = make<TileContent>();
                c->metadata = d.metadata;
                content = c;
            }
            content->addChild(n);
        }
    }
    if (d.children.empty()) {
        if (content) g->addChild(content);
        return gated(g, d, world);
    }
    // A content-less tile replacing a drawn one is read with its children, within the budget: the drawn tile
    // stays until all of them are there.
    if (!content && drawnAbove && !d.add && pass.budget >= d.children.size()) {
        for (uint32_t c : d.children) g->addChild(buildTile(s, c, world, true, pass));
        return gated(g, d, world);
    }
    const Sphere sp = inFrame(d.sphere, d.region, world);
    auto p = make<PagedLOD>();
    p->setFile(d.file, t);  // the tile's index: the load function's key
    p->setCenter(sp.center);
    p->setRadius(sp.radius);
    p->setScreenSpaceError(d.geometricError, s->options.maximumScreenSpaceError);
    if (content) (d.add ? static_cast<Group&>(*g) : static_cast<Group&>(*p)).addChild(content);
    g->addChild(p);
    return gated(g, d, world);
}

}  // namespace tiles

PageLoadFunction Tileset::loadFunction() const {
    std::shared_ptr<tiles::TilesetState> s = state_;
    return [s](const PageSource& source) -> ref_ptr<Node> {
        if (source.part == PagedLOD::kWholeFile) return loadGltfPage(source.file);  // a glTF paged inside a tile
        const uint32_t t = source.part;
        const tiles::TileDesc d = s->resolve(t);
        if (!d.world) throw LoadError(source.name(), d.path, "the tile's parent was not read");
        tiles::LoadPass pass{s->options.maxTilesPerLoad, nullptr};
        const bool drawn = !d.add && !d.contents.empty();
        auto g = make<Group>();
        for (uint32_t c : d.children) g->addChild(tiles::buildTile(s, c, *d.world, drawn, pass));
        // A content that may load later fails the whole load: its tiles are read together so that the tile
        // above stays drawn until all of them are there (no hole), and the pager asks for them again after its
        // back-off. Past TilesetOptions::transientAttempts the content is given up and the load succeeds.
        if (pass.retry) std::rethrow_exception(pass.retry);
        if (s->options.shareMeshes) s->meshes.share(*g);
        gltf::workOutSolids(*g);
        if (s->options.generateOccluders) generateOccluders(*g, s->options.occluders);
        return g;
    };
}

std::vector<std::string> Tileset::warnings() const { return state_->warnings(); }
TilesetCounts Tileset::counts() const { return state_->counts(); }
std::vector<TileFailure> Tileset::failures() const { return state_->failures(); }
std::shared_ptr<const Schema> Tileset::schema() const { return state_->top.schema; }
const std::optional<MetadataEntity>& Tileset::metadata() const { return state_->top.metadata; }
std::shared_ptr<const std::vector<MetadataEntity>> Tileset::groups() const { return state_->top.groups; }

Tileset loadTileset(const std::string& pathOrUrl, const TilesetOptions& options) {
    if (!(options.maximumScreenSpaceError > 0.0) || !std::isfinite(options.maximumScreenSpaceError))
        throw std::invalid_argument("loadTileset(): maximumScreenSpaceError must be finite and > 0");
    if (options.generateOccluders) options.occluders.validate("loadTileset()");
    Tileset ts;
    ts.file_ = pathOrUrl;
    ts.state_ = std::make_shared<tiles::TilesetState>(options);
    const uint32_t root = ts.state_->addTileset(pathOrUrl, readResource(pathOrUrl, options.resource), -1, -1);
    tiles::LoadPass pass{options.maxTilesPerLoad, nullptr};
    ts.root_ = tiles::buildTile(ts.state_, root, dmat4(1.0), false, pass);
    if (pass.retry) std::rethrow_exception(pass.retry);  // nothing retries this load: its caller may
    if (options.shareMeshes) ts.state_->meshes.share(*ts.root_);
    gltf::workOutSolids(*ts.root_);
    if (options.generateOccluders) generateOccluders(*ts.root_, options.occluders);
    return ts;
}

size_t refineAll(Node& root, const PageLoadFunction& load, unsigned attempts) {
    struct Collect : NodeVisitor {
        std::vector<PagedLOD*> found;
        void apply(PagedLOD& p) override {
            found.push_back(&p);
            traverse(p);
        }
    };
    size_t loaded = 0;
    std::unordered_set<PagedLOD*> seen;
    Collect c;
    root.accept(c);
    while (!c.found.empty()) {
        PagedLOD* p = c.found.back();
        c.found.pop_back();
        if (!seen.insert(p).second) continue;
        p->setTrigger(PagedLOD::Trigger::Command);
        if (p->detail()) continue;  // visited with its parent
        ref_ptr<Node> d;
        for (unsigned k = 1;; ++k) {
            try {
                d = load(PageSource{p->file(), p->part()});
                break;
            } catch (const std::exception&) {
                if (k >= attempts) throw;
            }
        }
        if (!d)
            throw LoadError(p->file(), "", "the load function returned no node for part " + std::to_string(p->part()));
        p->attachDetail(d, pageBytes(d.get()));
        ++loaded;
        d->accept(c);
    }
    return loaded;
}

bool isTilesetFile(const std::string& path) {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_size > (off_t(1) << 28)) return false;
    std::ifstream f(path, std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), {});
    if (tiles::sniffContent(bytes.data(), bytes.size()) != tiles::ContentKind::Json) return false;
    try {
        gltf::checkJsonDepth(path, bytes.data(), bytes.size());
        const auto j = nlohmann::json::parse(bytes.begin(), bytes.end());
        return j.is_object() && j.contains("asset") && j.contains("root");
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace sg
