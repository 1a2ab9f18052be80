// LAS 1.0-1.4 (ASPRS), point formats 0-10 uncompressed, read as a stream: the public header is checked once (every
// offset, length and count against the file's size), then records are read in large blocks and decoded with memcpy.
// The layout is that of the LAS 1.4 R15 specification (public header block, point data record formats 0-10).
#include "loaders/points/internal/ScanFile.h"
#include "loaders/points/internal/ScanFormats.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the LAS reader decodes little-endian records with memcpy"
#endif

namespace sg {
namespace {

// Public header sizes by version: 1.0-1.2, 1.3 (adds the waveform start), 1.4 (adds EVLRs and 64-bit counts).
constexpr uint16_t kHeaderSize[5] = {227, 227, 227, 235, 375};
// The smallest record of point formats 0-10; a file may append extra bytes to each record.
constexpr uint16_t kRecordLength[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
// Where a record's red, green, blue start (0: the format has no colour).
constexpr uint16_t kRgbOffset[11] = {0, 0, 20, 28, 0, 28, 0, 30, 30, 0, 30};
// Records are read this many bytes at a time: large enough that a read costs little per point.
constexpr size_t kBlockBytes = size_t(4) << 20;

const char* const kLazMessage =
    "LAZ (compressed LAS) is not read: convert it with `las2las -i in.laz -o out.las` (LAStools) or `pdal "
    "translate in.laz out.las`";

template <class T>
T get(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

[[noreturn]] void fail(const std::string& file, uint64_t offset, const std::string& reason) {
    throw LoadError(file, "offset " + std::to_string(offset), reason);
}

bool endsWithLaz(const std::string& path) {
    if (path.size() < 4) return false;
    std::string ext = path.substr(path.size() - 4);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".laz";
}

// What the reader takes from the public header, checked.
struct LasHeader {
    int minor = 0;
    unsigned format = 0;
    uint16_t recordLength = 0;
    uint64_t dataOffset = 0, count = 0;
    double scale[3] = {}, offset[3] = {};
};

// Scale and offset at header offsets 131 and 155: finite, the scale not 0, and such that no 32-bit coordinate can
// come out infinite (so that every point's position is finite without testing each).
void readScaleOffset(const std::string& file, const unsigned char* h, LasHeader& out) {
    for (int i = 0; i < 3; ++i) {
        const double s = get<double>(h + 131 + 8 * i), o = get<double>(h + 155 + 8 * i);
        const char axis = char('x' + i);
        if (!std::isfinite(s) || s == 0.0)
            fail(file, 131 + 8 * i,
                 std::string(1, axis) + " scale factor " + std::to_string(s) + " is not finite and non-zero");
        if (!std::isfinite(o)) fail(file, 155 + 8 * i, std::string(1, axis) + " offset is not finite");
        if (!std::isfinite(2147483648.0 * std::fabs(s) + std::fabs(o)))
            fail(file, 131 + 8 * i, std::string(1, axis) + " scale and offset make coordinates infinite");
        out.scale[i] = s;
        out.offset[i] = o;
    }
}

// The header's bounds (max x, min x, max y, min y, max z, min z at offset 179); empty when they are not finite or
// out of order: the points are still read, the bounds are only a hint.
Box readBounds(const unsigned char* h) {
    Box b;
    for (int i = 0; i < 3; ++i) {
        b.max[i] = get<double>(h + 179 + 16 * i);
        b.min[i] = get<double>(h + 187 + 16 * i);
    }
    if (!isFinite(b.min) || !isFinite(b.max) || b.empty()) return Box{};
    return b;
}

// Signature, version, header size, point format (LAZ refused), record length, data offset and count, each checked
// against the file's size.
LasHeader readHeader(const ScanFile& f, ScanInfo& info) {
    const std::string& file = f.path();
    if (f.size() < kHeaderSize[0])
        fail(file, 0, "truncated: " + std::to_string(f.size()) + " bytes, shorter than the 227-byte LAS header");
    unsigned char h[375] = {};
    f.readAt(0, h, size_t(std::min<uint64_t>(f.size(), sizeof h)));
    if (std::memcmp(h, "LASF", 4) != 0) fail(file, 0, "no LAS signature (\"LASF\")");
    LasHeader out;
    out.minor = h[25];
    if (h[24] != 1 || h[25] > 4)
        fail(file, 24, "LAS version " + std::to_string(h[24]) + "." + std::to_string(h[25]) + " (1.0 to 1.4 are read)");
    const uint16_t headerSize = get<uint16_t>(h + 94);
    if (headerSize < kHeaderSize[out.minor])
        fail(file, 94,
             "header size " + std::to_string(headerSize) + " is smaller than LAS 1." + std::to_string(out.minor) +
                 "'s " + std::to_string(kHeaderSize[out.minor]) + " bytes");
    if (headerSize > f.size())
        fail(file, 94, "truncated: the header of " + std::to_string(headerSize) + " bytes is longer than the file");
    const uint8_t formatByte = h[104];
    if ((formatByte & 0xc0) != 0 || endsWithLaz(file)) fail(file, 104, kLazMessage);
    out.format = formatByte;
    if (out.format > 10) fail(file, 104, "point format " + std::to_string(out.format) + " (0 to 10 are read)");
    out.recordLength = get<uint16_t>(h + 105);
    if (out.recordLength < kRecordLength[out.format])
        fail(file, 105,
             "point record length " + std::to_string(out.recordLength) + " is smaller than point format " +
                 std::to_string(out.format) + "'s " + std::to_string(kRecordLength[out.format]) + " bytes");
    out.dataOffset = get<uint32_t>(h + 96);
    if (out.dataOffset < headerSize || out.dataOffset > f.size())
        fail(file, 96,
             "offset to point data " + std::to_string(out.dataOffset) + " is outside the file's " +
                 std::to_string(headerSize) + " to " + std::to_string(f.size()) + " bytes");
    out.count = get<uint32_t>(h + 107);
    const uint64_t count64 = get<uint64_t>(h + 247);
    if (out.minor >= 4 && count64 != 0) out.count = count64;  // 1.4: the 64-bit count is the one that counts
    const uint64_t room = (f.size() - out.dataOffset) / out.recordLength;
    if (out.count > room)
        fail(file, out.minor >= 4 && count64 != 0 ? 247 : 107,
             std::to_string(out.count) + " points of " + std::to_string(out.recordLength) + " bytes from offset " +
                 std::to_string(out.dataOffset) + " run past the end of the file (" + std::to_string(f.size()) +
                 " bytes: room for " + std::to_string(room) + ")");
    readScaleOffset(file, h, out);
    info.format = "LAS 1." + std::to_string(out.minor) + " point format " + std::to_string(out.format);
    info.count = out.count;
    info.bounds = readBounds(h);
    info.hasColor = kRgbOffset[out.format] != 0;
    info.hasIntensity = true;
    info.hasNormal = false;
    return out;
}

class LasReader : public ScanReader {
public:
    explicit LasReader(const std::string& path) : file_(path) {
        header_ = readHeader(file_, info_);
        blockRecords_ = std::max<size_t>(1, kBlockBytes / header_.recordLength);
    }

    size_t read(std::vector<ScanPoint>& out, size_t max) override {
        const size_t n = size_t(std::min<uint64_t>(max, header_.count - next_));
        out.resize(n);
        for (size_t done = 0; done < n;) {
            const size_t block = std::min(n - done, blockRecords_);
            buffer_.resize(block * header_.recordLength);
            file_.readAt(header_.dataOffset + next_ * header_.recordLength, buffer_.data(), buffer_.size());
            if (info_.hasColor)
                decode<true>(block, out.data() + done);
            else
                decode<false>(block, out.data() + done);
            done += block;
            next_ += block;
        }
        return n;
    }

    void rewind() override { next_ = 0; }

private:
    template <bool kRgb>
    void decode(size_t n, ScanPoint* out) const {
        const unsigned char* p = buffer_.data();
        const size_t rgb = kRgbOffset[header_.format];
        const dvec3 scale(header_.scale[0], header_.scale[1], header_.scale[2]);
        const dvec3 offset(header_.offset[0], header_.offset[1], header_.offset[2]);
        for (size_t i = 0; i < n; ++i, p += header_.recordLength) {
            int32_t xyz[3];
            std::memcpy(xyz, p, sizeof xyz);
            ScanPoint& s = out[i];
            s.position = dvec3(xyz[0], xyz[1], xyz[2]) * scale + offset;
            s.intensity = get<uint16_t>(p + 12);
            s.normal = vec3(0.0f);
            if constexpr (kRgb) {
                uint16_t c[3];
                std::memcpy(c, p + rgb, sizeof c);
                s.color = glm::u8vec4(c[0] >> 8, c[1] >> 8, c[2] >> 8, 255);  // LAS colours are 16-bit
            } else {
                s.color = glm::u8vec4(255);
            }
        }
    }

    ScanFile file_;
    LasHeader header_;
    size_t blockRecords_ = 1;
    uint64_t next_ = 0;
    std::vector<unsigned char> buffer_;
};

}  // namespace

std::unique_ptr<ScanReader> openLas(const std::string& path) { return std::make_unique<LasReader>(path); }

}  // namespace sg
