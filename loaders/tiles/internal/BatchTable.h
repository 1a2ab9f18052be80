// A 3D Tiles 1.0 batch table (the JSON header and binary body of a b3dm or i3dm) made into a property store: one
// class, "batch_table", and one property table of batchLength rows whose columns stay in binary form. Internal:
// not installed.
#pragma once
#include "loaders/tiles/internal/TileFormats.h"
#include "sg/core/Properties.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace sg::tiles {

constexpr const char* kBatchTableClass = "batch_table";

// Null when the tile has no batch table (both sections empty). Throws LoadError(file, "batchTable.<name>...",
// reason) for a malformed one; what is left out goes to `warnings` as "path: what".
ref_ptr<PropertyStore> readBatchTable(const std::string& file, Bytes json, Bytes binary, uint32_t batchLength,
                                      std::vector<std::string>& warnings);

namespace batch {

// The 3D Tiles 1.0 componentType names ("BYTE" ... "DOUBLE") as the metadata's; None for any other.
ComponentType componentOf(const std::string& name);

// The class and table being made. Buffer 0 of the store is the binary body as it is; buffer 1 (`encoded`) holds
// the columns made from JSON values.
struct Columns {
    const std::string& file;
    Bytes binary;
    uint32_t count = 0;  // batchLength
    std::vector<std::string>& warnings;
    ClassDef cls;
    PropertyTable table;
    std::vector<uint8_t> encoded;

    // One JSON value per feature (null or a JSON null: no value) as a column of the narrowest type that holds
    // them all (see BatchTable.cpp).
    void addJson(const std::string& id, const std::vector<const nlohmann::ordered_json*>& values,
                 const std::string& path);
    // A {byteOffset, componentType, type} reference to `count` elements of the binary body.
    void addBinary(const std::string& id, const nlohmann::ordered_json& ref, const std::string& path);
    // Where `count` elements of `components` components of type `c` start in the binary body, per `ref`'s
    // byteOffset (at `path`.byteOffset): checked aligned and inside.
    uint64_t binaryOffset(const nlohmann::ordered_json& ref, ComponentType c, int components, uint64_t count,
                          const std::string& path) const;
    // Room for `bytes` more encoded bytes, else LoadError at `path` (values a hierarchy repeats per feature could
    // otherwise grow without bound).
    void reserve(uint64_t bytes, const std::string& path) const;
    void warn(const std::string& path, const std::string& what) { warnings.push_back(path + ": " + what); }
};

// Element i (of `components` components of type c) at `data` as JSON: an integer, a number, or an array of them.
nlohmann::ordered_json jsonElement(const unsigned char* data, ComponentType c, int components, uint64_t i);

// 3DTILES_batch_table_hierarchy flattened into per-feature columns (see BatchTableHierarchy.cpp).
void addHierarchy(Columns& c, const nlohmann::ordered_json& ext, const std::string& path);

}  // namespace batch
}  // namespace sg::tiles
