// The binary tile formats of OGC 3D Tiles 1.0 (b3dm, i3dm, cmpt; a pnts' point count), parsed into views of the
// caller's buffer for the tileset reader. Point clouds are made into nodes by readPnts (Pnts.h); the reads all
// formats share are in FeatureTable.h. Internal: not installed.
#pragma once
#include "loaders/gltf/Gltf.h"  // sg::LoadError(file, jsonPath, reason)
#include "sg/core/Math.h"       // dvec3, dmat4 (glm, double)

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sg::tiles {

enum class ContentKind { Glb, Json, B3dm, I3dm, Cmpt, Pnts, Unknown };
// By the first bytes: "glTF", "b3dm", "i3dm", "cmpt", "pnts"; Json when the first non-whitespace byte (after an
// optional UTF-8 BOM) is '{'.
ContentKind sniffContent(const unsigned char* data, size_t size);

struct Bytes {  // a view into the caller's buffer
    const unsigned char* data = nullptr;
    size_t size = 0;
};

struct B3dm {
    Bytes glb;  // the embedded binary glTF (its own length, without the tile's trailing padding)
    bool hasRtcCenter = false;
    dvec3 rtcCenter{0.0};  // feature table RTC_CENTER
    uint32_t batchLength = 0;
    Bytes batchJson, batchBinary;  // the batch table's sections (empty when absent; see BatchTable.h)
};

struct I3dm {
    Bytes glb;           // gltfFormat 1: the embedded glb
    std::string glbUri;  // gltfFormat 0: the URI of the glTF (trailing NULs/spaces trimmed); empty for format 1
    // One matrix per instance, in the tile's frame (z-up): translate(RTC_CENTER + position) * rotation * scale.
    // Rotation: columns NORMAL_RIGHT, NORMAL_UP, cross(right, up) (float or oct-encoded NORMAL_UP_OCT32P /
    // NORMAL_RIGHT_OCT32P), or EAST_NORTH_UP (east, north, up of WGS84 at the instance's position in ECEF, as
    // the 3D Tiles spec defines it), identity otherwise. Scale: SCALE or SCALE_NON_UNIFORM.
    // Positions: POSITION (float32 vec3) or POSITION_QUANTIZED (uint16 vec3) with QUANTIZED_VOLUME_OFFSET/SCALE.
    std::vector<dmat4> instances;
    // BATCH_ID per instance (empty when absent: an instance's index is its batch id); the batch table has
    // INSTANCES_LENGTH rows, as CesiumJS reads it.
    std::vector<uint32_t> batchIds;
    Bytes batchJson, batchBinary;
};

struct Cmpt {
    std::vector<Bytes> tiles;  // inner tiles in order (their own headers intact); nested cmpt is flattened
};

// Each throws LoadError (file, the JSON path or header field at fault, the reason) on malformed input.
B3dm parseB3dm(const std::string& file, const unsigned char* data, size_t size);
I3dm parseI3dm(const std::string& file, const unsigned char* data, size_t size);
Cmpt parseCmpt(const std::string& file, const unsigned char* data, size_t size);
// Header + POINTS_LENGTH only (readPnts in Pnts.h reads the points).
uint32_t pntsPointCount(const std::string& file, const unsigned char* data, size_t size);

}  // namespace sg::tiles
