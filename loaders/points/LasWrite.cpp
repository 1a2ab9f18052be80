// LasWriter: LAS 1.4 point format 7 (x, y, z, intensity, RGB), no variable-length records. Records go through a
// buffer; the header is written first with no points and rewritten at close() with the count and bounds. The bytes
// depend on the points alone (no creation date, a fixed system identifier), so equal inputs give equal files.
#include "loaders/points/Scan.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the LAS writer encodes little-endian records with memcpy"
#endif

namespace sg {
namespace {

constexpr size_t kHeaderSize = 375;   // LAS 1.4's public header
constexpr size_t kRecordLength = 36;  // point format 7
constexpr size_t kFlushBytes = size_t(1) << 20;

template <class T>
void put(unsigned char* p, T v) {
    std::memcpy(p, &v, sizeof v);
}

// One record of point format 7: return 1 of 1, unclassified, no GPS time.
void encode(unsigned char* p, const int32_t q[3], const ScanPoint& s) {
    std::memset(p, 0, kRecordLength);
    std::memcpy(p, q, 12);
    put<uint16_t>(p + 12, s.intensity);
    p[14] = 0x11;  // return number 1, number of returns 1 (bits 0-3 and 4-7)
    for (int c = 0; c < 3; ++c) put<uint16_t>(p + 30 + 2 * c, uint16_t(s.color[c] * 257));  // 255 -> 65535
}

}  // namespace

struct LasWriter::Impl {
    std::string path;
    std::FILE* file = nullptr;
    double scale = 0.001;
    dvec3 origin{0.0};
    uint64_t count = 0;
    Box bounds;  // of the positions as stored (what a reader gets back)
    std::vector<unsigned char> buffer;

    [[noreturn]] void failIo(const char* what) const {
        throw std::runtime_error("LasWriter: cannot " + std::string(what) + " " + path + ": " + std::strerror(errno));
    }

    void flush() {
        if (!buffer.empty() && std::fwrite(buffer.data(), 1, buffer.size(), file) != buffer.size()) failIo("write");
        buffer.clear();
    }

    std::vector<unsigned char> header() const {
        std::vector<unsigned char> h(kHeaderSize, 0);
        std::memcpy(h.data(), "LASF", 4);
        put<uint16_t>(&h[6], 0x10);  // global encoding: the coordinate system would be WKT (required for formats 6-10)
        h[24] = 1;
        h[25] = 4;
        std::memcpy(&h[26], "sgkit", 5);  // system identifier
        std::memcpy(&h[58], "sgkit", 5);  // generating software; creation day and year stay 0
        put<uint16_t>(&h[94], uint16_t(kHeaderSize));
        put<uint32_t>(&h[96], uint32_t(kHeaderSize));  // offset to point data: no VLRs
        h[104] = 7;
        put<uint16_t>(&h[105], uint16_t(kRecordLength));
        // The legacy counts (offsets 107 and 111) stay 0, as LAS 1.4 asks for formats 6-10.
        for (int i = 0; i < 3; ++i) {
            put<double>(&h[131 + 8 * i], scale);
            put<double>(&h[155 + 8 * i], origin[i]);
            put<double>(&h[179 + 16 * i], count ? bounds.max[i] : 0.0);
            put<double>(&h[187 + 16 * i], count ? bounds.min[i] : 0.0);
        }
        put<uint64_t>(&h[247], count);
        put<uint64_t>(&h[255], count);  // all first returns
        return h;
    }

    void finish() {
        flush();
        const std::vector<unsigned char> h = header();
        if (std::fseek(file, 0, SEEK_SET) != 0 || std::fwrite(h.data(), 1, h.size(), file) != h.size()) failIo("write");
        std::FILE* f = file;
        file = nullptr;
        if (std::fclose(f) != 0) failIo("close");
    }
};

LasWriter::LasWriter(const std::string& path, double scale) : impl_(std::make_unique<Impl>()) {
    if (!std::isfinite(scale) || scale <= 0.0)
        throw std::invalid_argument("LasWriter: scale " + std::to_string(scale) + " is not finite and positive");
    impl_->path = path;
    impl_->scale = scale;
    impl_->file = std::fopen(path.c_str(), "wb");
    if (!impl_->file) impl_->failIo("open");
    impl_->buffer = impl_->header();  // a placeholder until close()
    impl_->buffer.reserve(kFlushBytes + kRecordLength);
}

LasWriter::~LasWriter() {
    if (!impl_->file) return;
    try {
        impl_->finish();
    } catch (const std::exception&) {
        if (impl_->file) std::fclose(impl_->file);
    }
}

void LasWriter::setOrigin(const dvec3& origin) {
    if (impl_->count > 0) throw std::logic_error("LasWriter::setOrigin(): points were written already");
    if (!isFinite(origin)) throw std::invalid_argument("LasWriter::setOrigin(): the origin is not finite");
    impl_->origin = origin;
}

void LasWriter::write(const std::vector<ScanPoint>& points) {
    Impl& w = *impl_;
    if (!w.file) throw std::logic_error("LasWriter::write(): " + w.path + " is closed");
    for (const ScanPoint& p : points) {
        int32_t q[3] = {};
        dvec3 stored(0.0);
        for (int c = 0; c < 3; ++c) {
            const double units = std::round((p.position[c] - w.origin[c]) / w.scale);
            if (!(units >= -2147483648.0 && units <= 2147483647.0))  // NaN fails too
                throw std::invalid_argument("LasWriter::write(): point " + std::to_string(w.count) + " of " + w.path +
                                            " cannot be stored in 32 bits at scale " + std::to_string(w.scale));
            q[c] = int32_t(units);
            stored[c] = q[c] * w.scale + w.origin[c];
        }
        const size_t at = w.buffer.size();
        w.buffer.resize(at + kRecordLength);
        encode(&w.buffer[at], q, p);
        w.bounds.expand(stored);
        ++w.count;
        if (w.buffer.size() >= kFlushBytes) w.flush();
    }
}

void LasWriter::close() {
    if (impl_->file) impl_->finish();
}

}  // namespace sg
