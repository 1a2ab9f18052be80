// Scans as users have them (LAS 1.2-1.4, PLY): read as a stream of points in double precision (for a tile builder
// that does not hold the scan in memory), or whole into a node; and LAS written (the simulated scanner's output).
#pragma once
#include "loaders/gltf/Gltf.h"  // sg::LoadError
#include "sg/core/Math.h"
#include "sg/core/Node.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sg {

// One point of a scan, in the file's coordinates (LAS: scale and offset applied).
struct ScanPoint {
    dvec3 position{0.0};
    glm::u8vec4 color{255, 255, 255, 255};  // RGBA (LAS's and PLY's 16-bit colours are taken to 8 bits)
    uint16_t intensity = 0;
    vec3 normal{0.0f};  // zero where the file has none
};

// What a scan's header says.
struct ScanInfo {
    std::string format;  // for messages and sgview --info: "LAS 1.4 point format 7", "PLY binary_little_endian"
    uint64_t count = 0;  // points in the file
    Box bounds;          // from the header (LAS); empty where the file does not say (PLY)
    bool hasColor = false, hasIntensity = false, hasNormal = false;
};

// Reads a scan's points in order, a chunk at a time. Every read checks what it reads: a LoadError names the file,
// the byte offset (as the JSON path argument: "offset 1234") or the PLY line, and the reason.
class ScanReader {
public:
    virtual ~ScanReader() = default;
    const ScanInfo& info() const { return info_; }
    // Replaces `out` with the next points, at most `max` of them; returns how many (0 once all are read). A point whose
    // position is not finite is a LoadError (naming its index).
    virtual size_t read(std::vector<ScanPoint>& out, size_t max) = 0;
    // Back to the first point (a builder reads the scan more than once).
    virtual void rewind() = 0;

protected:
    ScanInfo info_;
};

// Opens LAS or PLY by their first bytes ("LASF", "ply"); a LAZ file (LAS compressed, the header's point format with
// bit 7 set) is refused with a LoadError that says how to convert it (`las2las` or `pdal translate` to LAS); anything
// else is a LoadError naming the file.
std::unique_ptr<ScanReader> openScan(const std::string& path);

struct ScanLoadOptions {
    // Points kept at most (every k-th point past it, evenly); 0: all.
    uint64_t maxPoints = 0;
};

// The whole scan as a Transform placed at its bounds' centre, holding one Geometry of points (Mesh::setPoints, with
// colours, intensities and normals where the file has them, the point spacing estimated from the bounds and the
// count), so that float positions stay exact near the centre whatever the file's coordinates. An empty scan is a
// LoadError ("no points").
ref_ptr<Node> loadScan(const std::string& path, const ScanLoadOptions& options = {});

// Writes points as LAS 1.4 point format 7 (x, y, z, intensity, RGB; 16-bit colours from the 8-bit ones x 257) with
// the given scale (metres per unit of the stored integers) and the offset setOrigin gives (0 by default). Throws
// std::runtime_error naming the file when it cannot be written, std::invalid_argument for a point that the scale
// cannot store in 32 bits.
class LasWriter {
public:
    LasWriter(const std::string& path, double scale = 0.001);
    ~LasWriter();
    LasWriter(const LasWriter&) = delete;
    LasWriter& operator=(const LasWriter&) = delete;
    // The offset must be known before the first point: points are stored relative to `origin` (defaults to 0).
    void setOrigin(const dvec3& origin);
    void write(const std::vector<ScanPoint>& points);
    // Writes the header (count, bounds) and closes the file; the destructor closes without throwing.
    void close();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace sg
