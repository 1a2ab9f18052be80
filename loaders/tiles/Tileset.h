// OGC 3D Tiles 1.0 and 1.1 read as a graph of paged nodes: every tile with children is a PagedLOD refined by
// screen-space error, its content the coarse level and its children's contents, loaded together, the detail.
// Contents: .glb and .gltf (glTF's +Y up turned to the tileset's +Z up), .b3dm, .i3dm (Instances), .cmpt and
// external tilesets; .pnts is skipped with a warning. Files and http(s) URLs (loaders/net/Resource.h).
#pragma once
#include "loaders/gltf/Gltf.h"
#include "loaders/net/Resource.h"
#include "loaders/tiles/TileMetadata.h"
#include "sg/core/Math.h"
#include "sg/core/Node.h"
#include "sg/paging/Pager.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sg {

struct TilesetOptions {
    // A tile refines while its geometric error, seen at the eye's distance to its bounding sphere, projects to
    // more than this many pixels (Cesium's default).
    double maximumScreenSpaceError = 16.0;
    // Content-less tiles below a drawn tile are read with their children in one load (so that the drawn tile
    // stays until everything replacing it is there), up to this many tiles per load; past it they page alone.
    size_t maxTilesPerLoad = 256;
    // Meshes equal to the bit in different tiles' contents become one mesh (held, welded and uploaded once), as a
    // city's building kinds repeated in every tile's file. The pager's byte budget still counts a shared mesh in
    // each detail that holds it.
    bool shareMeshes = true;
    // Occluders made from each load's geometry as it is read (sg::generateOccluders, sg/build/GeneratedOccluders.h),
    // on the loader's thread: the occlusion pass uses a tile's while its content is drawn. Tiles that carry sgkit's
    // own authored occluders keep them.
    bool generateOccluders = false;
    OccluderGenSettings occluders;
    ResourceOptions resource;
    // A content whose read fails for a reason that may pass (a timeout, HTTP 5xx, a refused, reset or dropped
    // connection) fails its load, which the pager asks for again after its back-off; the load failing for it this
    // many times, the next failure is final as a missing file's (Tileset::failures()), so that the tiles read with
    // it show. The root tile's content is read by loadTileset, which nothing retries: a transient failure there
    // throws from it (unless this is 1).
    unsigned transientAttempts = 4;
};

// A tile content that could not be read or parsed. Final: the tile is drawn without it (its children load and
// draw), as for a missing file (HTTP 404, no such file) or a corrupt one, a warning naming it. Not final (a
// network failure that may pass): the load holding the tile failed and is asked for again (TilesetOptions::
// transientAttempts). A content that loads later is taken off the list.
struct TileFailure {
    std::string file;    // the tileset.json holding the tile
    std::string path;    // the JSON path of the content's URI: "root.children[3].content.uri", or an implicit
                         // tile's template with its coordinates ("root.content.uri (implicit tile 2/1/3)")
    std::string uri;     // the content, resolved
    std::string reason;  // what failed: the LoadError's text
    bool final = false;
    unsigned attempts = 0;  // loads it failed
};

// What a tileset holds and what was loaded so far (loads on the pager's threads add to it).
struct TilesetCounts {
    size_t tiles = 0;     // tiles read from tileset.json files (external ones as they are loaded)
    size_t contents = 0;  // contents loaded
    size_t externalTilesets = 0;
    size_t points = 0;        // points loaded (pnts contents and glTF point meshes)
    size_t sharedMeshes = 0;  // meshes replaced by an equal one another tile had loaded (shareMeshes)
    size_t pooledMeshes = 0;  // distinct meshes the tileset's loads hold now
    size_t failed = 0;        // contents that failed and have not loaded since (Tileset::failures())
};

namespace tiles {
class TilesetState;  // the tile table shared by the graph's load function (loaders/tiles/TilesetRead.cpp)
}

class Tileset {
public:
    // The graph: the root tile's Transform (its transform and content) with the PagedLODs below; +Z up, in the
    // tileset's frame (Earth-centred for georeferenced data: the renderer draws relative to the camera).
    ref_ptr<Node> root() const { return root_; }
    // The pager's load function for this tileset's PagedLODs (sg::Pager, Viewer::enablePaging). Files that are
    // not this tileset's tiles are read as glTF pages (sg::loadGltfPage). Safe on several loader threads.
    PageLoadFunction loadFunction() const;
    // What was skipped or converted, each naming its file and JSON path; loads add theirs.
    std::vector<std::string> warnings() const;
    TilesetCounts counts() const;
    // The contents that failed to load and have not loaded since, by tile (loads add theirs).
    std::vector<TileFailure> failures() const;
    const std::string& file() const { return file_; }
    // The tileset's 3D Tiles 1.1 schema (null without one), its own metadata and its groups (which a content's
    // TileMetadata::Content::group indexes). A tile's metadata: tileMetadataOf() on a node of its content.
    std::shared_ptr<const Schema> schema() const;
    const std::optional<MetadataEntity>& metadata() const;
    std::shared_ptr<const std::vector<MetadataEntity>> groups() const;

private:
    friend Tileset loadTileset(const std::string&, const TilesetOptions&);
    std::shared_ptr<tiles::TilesetState> state_;
    ref_ptr<Node> root_;
    std::string file_;
};

// Reads tileset.json (a path or an http(s) URL) and the root tile's content. Throws LoadError naming the file,
// the JSON path and the reason (e.g. "root.children[3].geometricError: missing"); a JSON file that is not a
// tileset (a glTF, say) is refused. A tile content that is missing or corrupt (the root's too) is a warning and a
// TileFailure, here and in the loads: the tile is drawn without it.
Tileset loadTileset(const std::string& pathOrUrl, const TilesetOptions& options = {});

// Loads every tile below `root` now, on this thread (sgview --refine-all, tests): each PagedLOD gets its detail
// attached and shows it whenever attached (Trigger::Command), so that a REPLACE tile's content gives way to its
// children's and an ADD tile's stays. A load that throws is tried again at once, `attempts` times in all (a
// tileset's: TilesetOptions::transientAttempts, past which its loads do not throw for a content); then refineAll
// throws what it threw. Returns the tiles loaded.
size_t refineAll(Node& root, const PageLoadFunction& load, unsigned attempts = 1);

// Whether a file's JSON is a 3D Tiles tileset (an object with "asset" and "root"): what sgview asks before
// choosing a reader. False for anything else, including files it cannot read.
bool isTilesetFile(const std::string& path);

}  // namespace sg
