// The tileset reader's internal pieces (not installed): the tile table read from tileset.json files, shared
// by the graph's load function on the pager's threads, and the reading of one tile's contents into nodes.
#pragma once
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/internal/SharedMeshes.h"
#include "loaders/tiles/internal/TilesetMetadata.h"

#include <nlohmann/json_fwd.hpp>

#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace sg::tiles {

struct Sphere {
    dvec3 center{0.0};
    double radius = 0.0;
};

// A tile metadata property whose semantic the reader applies (3D Tiles 1.1 metadata semantics): its name in its
// class and its FLOAT32 or FLOAT64 components (12 for a box, 6 a region, 4 a sphere, 1 a geometric error).
struct SemanticProperty {
    SemanticProperty(std::string n = "", bool f64 = true, uint32_t c = 1)
        : name(std::move(n)), float64(f64), components(c) {}
    std::string name;
    bool float64 = true;
    uint32_t components = 1;
    // The class's offset and scale, one per component (empty: 0 and 1); a property table may override them.
    std::vector<double> offset, scale;
};
// An offset or scale of `n` components (a number for 1, an array of n numbers otherwise) into `out`; false when
// `v` is neither.
bool transformComponents(const nlohmann::json& v, uint32_t n, std::vector<double>& out);
// A metadata class's properties that give a tile's volume and geometric error, and what is wrong with them if
// anything (raised when a subtree uses the class: file, JSON path, reason).
struct TileSemantics {
    std::optional<SemanticProperty> box, region, sphere, error;
    std::optional<std::tuple<std::string, std::string, std::string>> problem;
};
using MetadataSchema = std::map<std::string, TileSemantics>;  // by class name

// Implicit tiling (3D Tiles 1.1): a tile subdivided as a quadtree or octree written as URI templates, with
// which tiles and contents exist in availability bitstreams of subtree files (TilesetImplicit.cpp).
struct ImplicitTiling {
    bool octree = false;
    uint32_t subtreeLevels = 0, availableLevels = 0;
    std::string subtrees;                   // URI template of the subtree files, resolved against the tileset
    std::vector<std::string> contents;      // URI templates of the contents, resolved
    std::vector<std::string> contentPaths;  // their JSON paths ("root.content.uri"), for messages
    bool region = false;
    std::vector<double> volume;  // the root's box (12 numbers) or region (6)
    double geometricError = 0.0;
    MetadataSchema schema;  // the tileset's, for the subtrees' tile metadata
    // The tileset file's whole schema and groups (null without them), for the subtrees' tile and content metadata,
    // and each content template's group (-1: none).
    std::shared_ptr<const Schema> fullSchema;
    std::shared_ptr<const std::vector<MetadataEntity>> groups;
    std::vector<int> contentGroups;
};

// A subtree file's availability: of its tiles (levels 0 .. subtreeLevels - 1, Morton order per level), of each
// content, and of the subtrees below its last level.
struct Availability {
    bool constant = false, value = false;
    std::vector<uint8_t> bits;  // little-endian bit order, as the specification's bitstreams
    bool operator[](uint64_t i) const { return constant ? value : (bits[size_t(i >> 3)] >> (i & 7)) & 1; }
    // Set bits before bit i: a tile's row in the subtree's metadata (after countBits()).
    uint64_t rank(uint64_t i) const;
    uint64_t countBits(uint64_t bits);  // the set bits of the first `bits`; prepares rank()
    std::vector<uint64_t> before;       // set bits before each byte
};
struct Subtree {
    Availability tiles, children;
    std::vector<Availability> contents;
    // Tile metadata with the semantics the reader applies, a row per available tile (in availability order):
    // the tile's volume in the implicit root's frame (Earth-centred for a region) and its geometric error.
    enum class Volume { None, Box, Region, Sphere } volume = Volume::None;
    std::vector<double> volumes;  // 12, 6 or 4 numbers a row
    std::vector<double> errors;   // empty without TILE_GEOMETRIC_ERROR
    // Every property of the tile and content metadata (TilesetImplicitMetadata.h): tables of `store` with a row per
    // available tile, or per available content of each content; -1 where the subtree has none.
    ref_ptr<const PropertyStore> store;
    int tileTable = -1;
    std::vector<int> contentTables;     // one per content of the tiling
    std::vector<std::string> warnings;  // what was left out, each naming its JSON path
};
// Reads a subtree file (binary "subt" or JSON), its tile and content metadata with it: `readBuffer` reads an
// external buffer by its resolved URI. Throws LoadError naming the file, the JSON path and the reason (e.g. a
// bitstream shorter than its level count, a metadata table with other than a row per available tile, a negative
// geometric error).
Subtree parseSubtree(const std::string& file, const std::vector<unsigned char>& bytes, const ImplicitTiling& tiling,
                     const std::function<std::vector<unsigned char>(const std::string&)>& readBuffer);
// Morton index of (x, y) or (x, y, z): bits interleaved, x lowest.
uint64_t morton(uint32_t x, uint32_t y, uint32_t z, bool octree);
// A template's {level}, {x}, {y} and {z} replaced.
std::string expandTemplate(std::string t, uint32_t level, uint32_t x, uint32_t y, uint32_t z);
// The sphere of implicit tile (level, x, y, z) and whether it is Earth-centred (a region).
Sphere implicitSphere(const ImplicitTiling& t, uint32_t level, uint32_t x, uint32_t y, uint32_t z);
// The sphere through a box's corners (12 numbers: centre and three half axes); the Earth-centred sphere holding a
// region (6 numbers); what is wrong with a region's numbers, or nothing.
Sphere boxSphere(const double* box);
Sphere regionSphere(const std::vector<double>& region);
std::string badRegion(const double* region);
// The tile metadata classes of a tileset's `schema` (or the file its `schemaUri` names, read with `options`);
// with `full`, the whole schema too (null without one), its warnings added to `warnings`.
MetadataSchema readSchema(const std::string& file, const nlohmann::json& tileset, const ResourceOptions& options,
                          std::shared_ptr<const Schema>* full = nullptr, std::vector<std::string>* warnings = nullptr);

// One tile of a tileset.json, as read: its volume in its own frame (after its transform), or in the
// Earth-centred frame for a region (which no transform moves, as the specification says).
struct TileDesc {
    int64_t parent = -1;
    std::vector<uint32_t> children;
    dmat4 transform{1.0};
    bool hasTransform = false;
    Sphere sphere;
    bool region = false;  // sphere is Earth-centred
    double geometricError = 0.0;
    bool add = false;  // refine ADD (else REPLACE)
    // viewerRequestVolume: the tile is drawn and refined only with the eye inside this sphere (its box's or
    // region's bounding sphere), in the tile's frame, or Earth-centred for a region.
    std::optional<Sphere> request;
    bool requestRegion = false;
    std::vector<std::string> contents;      // resolved URIs
    std::vector<std::string> contentPaths;  // the JSON path of each ("root.children[3].content.uri"), for messages
    ref_ptr<const TileMetadata> metadata;   // its and its contents' 3D Tiles 1.1 metadata; null when none
    std::string file, path;                 // the tileset.json holding it and its JSON path, for messages
    uint32_t source = 0;                    // the tileset file (TilesetState's sources), for cycles
    uint32_t depth = 0;                     // below the root of the whole tileset
    std::optional<dmat4> world;             // its frame in the graph's, set when its node is built
    // An implicit tile: its tiling and coordinates; `pending` until its contents and children are read from its
    // subtree (TilesetState::resolve).
    std::shared_ptr<const ImplicitTiling> implicit;
    uint32_t level = 0, x = 0, y = 0, z = 0;
    bool pending = false;
};

class TilesetState {
public:
    explicit TilesetState(TilesetOptions o) : options(std::move(o)) {}
    const TilesetOptions options;

    // Reads a tileset.json's tiles into the table; returns the root's index. `parentSource`: the tileset file
    // whose tile names this one as content (-1 for the top), whose chain a cycle is checked against;
    // `parentTile`: that tile (depth, inherited refinement). Throws LoadError.
    uint32_t addTileset(const std::string& file, const std::vector<unsigned char>& bytes, int64_t parentSource,
                        int64_t parentTile);
    TileDesc tile(uint32_t i) const;
    // The tile with its contents and children known: an implicit tile's read from its subtree file (loaded once
    // and kept), its available children added to the table. Throws LoadError for a bad subtree file.
    TileDesc resolve(uint32_t i);
    void setWorld(uint32_t i, const dmat4& world);

    void warn(std::string w);
    std::vector<std::string> warnings() const;
    // Content `c` of tile `t` (as `d` says it) failed with `e` (TilesetFailures.cpp): recorded as a TileFailure.
    // True when the failure is final (a missing or corrupt content, or a transient failure past
    // options.transientAttempts): a warning names it and the tile is built without it. False: the load should
    // throw, so that the pager tries it again.
    bool contentFailed(uint32_t t, const TileDesc& d, size_t c, const LoadError& e);
    // Content `uri` of tile `t` loaded: counted, and a failure recorded for it before taken off the list.
    void contentLoaded(uint32_t t, const std::string& uri);
    std::vector<TileFailure> failures() const;
    TilesetCounts counts() const;
    void countPoints(size_t points);
    // Equal meshes of different loads made one (TilesetOptions::shareMeshes).
    SharedMeshes meshes;
    // The top tileset file's schema, metadata and groups (set by its addTileset, read-only after).
    FileMetadata top;

private:
    struct Source {
        std::string file;
        int64_t parent;
    };
    mutable std::mutex mutex_;
    std::deque<TileDesc> tiles_;
    std::vector<Source> sources_;
    std::map<std::tuple<const ImplicitTiling*, uint32_t, uint32_t, uint32_t, uint32_t>, std::shared_ptr<const Subtree>>
        subtrees_;
    std::vector<std::string> warnings_;
    std::map<std::pair<uint32_t, std::string>, TileFailure> failures_;  // by tile and content URI
    TilesetCounts counts_;
};

// What one load (loadTileset's, or one of the load function's) carries through the tiles it builds.
struct LoadPass {
    size_t budget = 0;         // tiles it may still read
    std::exception_ptr retry;  // the first content failure that may pass: the load throws it once built
};

// The graph of tile `t` in its parent's frame: its Transform, content and (with children) a PagedLOD whose detail
// is the children's graphs. `world`: the parent's frame in the graph's. `drawnAbove`: an ancestor's content is
// drawn until this tile's replaces it (content-less tiles are then read with their children, see TilesetOptions).
// A content that fails is left out (TilesetState::contentFailed), its failure kept in `pass` when it may pass.
// Throws LoadError for a subtree file that cannot be read.
ref_ptr<Node> buildTile(const std::shared_ptr<TilesetState>& s, uint32_t t, const dmat4& parentWorld, bool drawnAbove,
                        LoadPass& pass);

// One content (a URI) as nodes in its tile's frame. External tilesets become their root
// tile's graph. `tile`: the tile naming it. Throws LoadError when it cannot be read or parsed.
ref_ptr<Node> loadContent(const std::shared_ptr<TilesetState>& s, uint32_t tile, const std::string& uri,
                          const dmat4& world, LoadPass& pass);

// glTF's +Y up to 3D Tiles' +Z up: (x, y, z) -> (x, -z, y).
dmat4 yUpToZUp();

}  // namespace sg::tiles
