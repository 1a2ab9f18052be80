// The reading of 3D Tiles 1.1 metadata entities (a tileset's, its groups', a tile's, a content's) from
// tileset.json against the tileset's schema. Internal: not installed.
#pragma once
#include "loaders/tiles/TileMetadata.h"

#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sg::tiles {

// What a tileset file declares: its schema (null without one), its own metadata and its groups.
struct FileMetadata {
    std::shared_ptr<const Schema> schema;
    std::optional<MetadataEntity> metadata;
    std::shared_ptr<const std::vector<MetadataEntity>> groups;
};

// The tileset's `metadata` and `groups`, against `schema` (null when the file has none). Throws LoadError.
FileMetadata readFileMetadata(const std::string& file, const nlohmann::json& tileset,
                              std::shared_ptr<const Schema> schema, std::vector<std::string>& warnings);

// An entity ({"class": ..., "properties": {...}}) at `path`: each value checked against its class property's
// type and transformed by its offset, scale and normalized. Throws LoadError (no schema, an unknown class, a
// value of the wrong type, a required property missing); a property the class lacks is a warning.
MetadataEntity readEntity(const std::string& file, const nlohmann::json& j, const Schema* schema,
                          const std::string& path, std::vector<std::string>& warnings);

// A class property's value as a JSON entity gives it, made final: noData made the default (or Null); normalized,
// scaled and offset, component by component, for numbers.
PropertyValue entityValue(const Schema& schema, const ClassProperty& p, const nlohmann::json& v);

}  // namespace sg::tiles
