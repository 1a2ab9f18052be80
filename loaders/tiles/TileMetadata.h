// The 3D Tiles 1.1 metadata of a tileset's tiles and contents (and of the groups contents belong to), read from
// tileset.json (or an implicit tile's subtree file) with the schema's offset, scale and normalized applied, and
// reachable from a tile's content nodes.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Properties.h"

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sg {

// An entity's class and values: the class's properties the entity gives or whose default applies, in the
// schema's order (a value equal to the property's noData reads as its default, or Null).
struct MetadataEntity {
    std::string classId;
    std::vector<std::pair<std::string, PropertyValue>> properties;
    const PropertyValue* find(const std::string& id) const;  // null when absent
};

// One tile's metadata, shared by the nodes of its content. The schema and groups are those of the tileset file
// that declares the tile (an external tileset has its own).
class TileMetadata : public Referenced {
public:
    std::optional<MetadataEntity> tile;
    struct Content {
        std::optional<MetadataEntity> metadata;
        int group = -1;  // into *groups; -1: none
    };
    std::vector<Content> contents;  // one per content of the tile, in its order
    std::shared_ptr<const Schema> schema;
    std::shared_ptr<const std::vector<MetadataEntity>> groups;
};

// What a tile's contents made, below one Group that carries the tile's metadata (null when it has none).
class TileContent : public Group {
public:
    ref_ptr<const TileMetadata> metadata;
};

// The metadata of the tile whose content holds `n` (n or an ancestor by first parents is a TileContent): null
// when n is in no tile's content or that tile has no metadata.
const TileMetadata* tileMetadataOf(const Node& n);

}  // namespace sg
