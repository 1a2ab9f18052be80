// The parts the 3D Tiles 1.0 binary formats share: the header, the four table sections after it and the feature
// table (its JSON semantics and references into its binary body), each read checked against the bytes. Internal:
// not installed.
#pragma once
#include "loaders/tiles/internal/TileFormats.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace sg::tiles {

inline uint32_t le32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
inline uint16_t le16(const unsigned char* p) { return uint16_t(p[0] | p[1] << 8); }
inline float f32(const unsigned char* p) {
    const uint32_t u = le32(p);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

// The magic as text when printable, else in hex (it goes into a message).
std::string magicText(const unsigned char* p);

// The 12 bytes every format starts with: magic, version 1, byteLength equal to the bytes given; `headerSize` bytes
// at least. Errors name `prefix` + "header...".
void checkHeader(const std::string& file, const std::string& prefix, const unsigned char* data, size_t size,
                 const char* magic, size_t headerSize);

// A feature table: its JSON (an object) and its binary body; `count` below is the number of features (instances,
// points).
struct FeatureTable {
    const std::string& file;
    nlohmann::json json_;
    Bytes binary;

    static std::string path(const std::string& name) { return "featureTable." + name; }
    const nlohmann::json* find(const char* name) const;

    // The start of `count` elements of `components` values of `componentSize` bytes that `name` refers to in
    // the binary body; the byteOffset is a multiple of the component size, as the spec requires.
    const unsigned char* binaryRef(const char* name, const nlohmann::json& ref, size_t componentSize, size_t components,
                                   uint64_t count) const;
    // Semantics with one component type refuse another named in "componentType".
    void fixedType(const char* name, const nlohmann::json& ref, const char* type) const;
    // A global uint32: a JSON integer or a reference to an UNSIGNED_INT in the binary body.
    std::optional<uint32_t> globalUint(const char* name) const;
    // A global float32[3]: a JSON array of 3 finite numbers or a reference to 3 FLOATs in the binary body.
    std::optional<dvec3> globalVec3(const char* name) const;
    // A per-feature property: only in the binary body (the spec allows no JSON arrays); nullptr when absent.
    const unsigned char* perInstance(const char* name, const char* type, size_t componentSize, size_t components,
                                     uint32_t count) const;
};

// The sections after a 28- or 32-byte header: feature table (JSON, binary), batch table (JSON, binary), and
// what follows up to byteLength (the glb or the glTF URI; nothing for pnts).
struct Sections {
    FeatureTable featureTable;
    Bytes body;
    Bytes batchJson, batchBinary;
};
Sections readSections(const std::string& file, const unsigned char* data, size_t size, size_t headerSize);

// A unit vector oct-encoded as two unsigned integers in [0, range] (i3dm's oct32P: 65535, pnts' oct16P: 255), as
// CesiumJS' octDecodeInRange reads it.
dvec3 octDecode(uint32_t ex, uint32_t ey, double range);

// BATCH_ID per feature (UNSIGNED_SHORT unless its componentType says UNSIGNED_BYTE or UNSIGNED_INT); empty when
// absent.
std::vector<uint32_t> readBatchIds(const FeatureTable& ft, uint32_t n);

}  // namespace sg::tiles
