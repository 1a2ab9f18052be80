// A 3D Tiles 1.0 point cloud (.pnts) made into nodes, and the 3DTILES_draco_point_compression data it may hold.
// Internal: not installed.
#pragma once
#include "loaders/tiles/internal/FeatureTable.h"
#include "sg/core/Node.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sg::tiles {

// A Transform placed at RTC_CENTER (plus the quantized volume's offset for POSITION_QUANTIZED), in double, holding
// one Geometry of points relative to it (Mesh::setPoints: colours 0..1 from RGBA, RGB or RGB565, normals from NORMAL
// or NORMAL_OCT16P; CONSTANT_RGBA is the material's colour). In the tile's frame as it is: the format is +Z up, so
// no glTF axis change applies. Features: with BATCH_ID an attribute set over the batch table's BATCH_LENGTH rows;
// without, a batch table has a row per point and the set is implicit (a point's index is its feature). Throws
// LoadError(file, JSON path or header field, reason); what is left out goes to `warnings` as "path: what".
ref_ptr<Node> readPnts(const std::string& file, const unsigned char* data, size_t size,
                       std::vector<std::string>& warnings);

// The feature table's 3DTILES_draco_point_compression stream, decoded once: the semantics and batch table
// properties it names read from it (their byteOffsets are ignored, as the extension says).
class PntsDraco {
public:
    // Null when the feature table has no such extension. Throws LoadError for a malformed extension, a stream
    // that does not decode, or one whose point count is not `points`.
    static std::unique_ptr<PntsDraco> decode(const FeatureTable& ft, uint32_t points,
                                             std::vector<std::string>& warnings);
    ~PntsDraco();

    bool has(const std::string& semantic) const;
    // The semantic's values, `components` per point, converted to T (float, uint8_t or uint32_t).
    template <class T>
    std::vector<T> values(const std::string& semantic, int components) const;
    // The batch table with the properties its extension names decoded and appended to its binary, their
    // byteOffsets pointing there and the extension removed: what readBatchTable then reads as any other. False
    // (the outputs untouched) when the batch table names no compressed property.
    bool batchTable(Bytes json, Bytes binary, std::string& jsonOut, std::vector<unsigned char>& binaryOut);

private:
    struct Impl;
    explicit PntsDraco(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace sg::tiles
