// The tile and content metadata of implicit tiles (3D Tiles 1.1): a subtree's property tables read whole against
// the tileset's schema, and an implicit tile's TileMetadata made from their rows. Internal: not installed.
#pragma once
#include "loaders/tiles/internal/TilesetTable.h"

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>

namespace sg::tiles {

// The bytes of the subtree's buffer view whose index is `index` (named at `path`), checked against its buffer.
using SubtreeViews =
    std::function<std::pair<const unsigned char*, uint64_t>(const nlohmann::json& index, const std::string& path)>;

// Reads the property tables that the subtree JSON `doc` names as tileMetadata and contentMetadata into s.store
// (every property, against tiling.fullSchema) and sets s.tileTable and s.contentTables. `tiles`: the subtree's
// tile slots. A table must hold one row per available tile (or per available content of its content). Throws
// LoadError naming `file`, the JSON path and the reason.
void readSubtreeMetadata(const std::string& file, const nlohmann::json& doc, const ImplicitTiling& tiling,
                         uint64_t tiles, const SubtreeViews& views, Subtree& s);

// The metadata of the implicit tile at bit `at` of subtree `s`: its row of the tile table, its available contents'
// rows and groups (one per available content, in order), with the tiling's schema and groups. `own`: the metadata
// tileset.json gives the tile (an implicit root's), whose tile entity stands where the subtree has none. Null when
// there is no metadata.
ref_ptr<const TileMetadata> implicitTileMetadata(const ImplicitTiling& tiling, const Subtree& s, uint64_t at,
                                                 const TileMetadata* own);

}  // namespace sg::tiles
