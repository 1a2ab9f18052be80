// The point tile builder's addressing and files: the cube's cells, octree paths, point records and part files.
#include "loaders/points/internal/PointTilerDetail.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace sg::pointtiles {

glm::u32vec3 Cube::cell(const dvec3& p) const {
    const double cells = double(uint32_t(1) << kMaxLevel);
    glm::u32vec3 q;
    for (int a = 0; a < 3; ++a) {
        const double f = std::floor((p[a] - min[a]) / size * cells);
        q[a] = f > 0.0 ? uint32_t(std::min(f, cells - 1.0)) : 0u;  // NaN to 0 as well
    }
    return q;
}

NodeId NodeId::child(int i) const {
    NodeId c;
    c.path = path + char('0' + i);
    c.level = level + 1;
    c.index = index * uint64_t(2) + glm::u64vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    return c;
}

NodeId NodeId::fromPath(const std::string& path) {
    if (path.empty() || path[0] != 'r' || path.size() > size_t(kMaxLevel) + 1)
        throw std::runtime_error("not an octree path: \"" + path + "\"");
    NodeId n;
    for (size_t i = 1; i < path.size(); ++i) {
        if (path[i] < '0' || path[i] > '7') throw std::runtime_error("not an octree path: \"" + path + "\"");
        n = n.child(path[i] - '0');
    }
    return n;
}

namespace {

void put(char*& p, const void* v, size_t n) {
    std::memcpy(p, v, n);
    p += n;
}

void get(const char*& p, void* v, size_t n) {
    std::memcpy(v, p, n);
    p += n;
}

std::string encode(const std::vector<Point>& points) {
    std::string bytes(points.size() * kRecordBytes, '\0');
    char* p = bytes.data();
    for (const Point& pt : points) {
        put(p, &pt.position[0], 24);
        put(p, &pt.order, 8);
        put(p, &pt.color[0], 4);
        put(p, &pt.intensity, 2);
        p += 2;  // padding: records of 40 bytes
    }
    return bytes;
}

}  // namespace

std::vector<Point> decodeRecords(const char* p, size_t count) {
    std::vector<Point> points(count);
    for (Point& pt : points) {
        get(p, &pt.position[0], 24);
        get(p, &pt.order, 8);
        get(p, &pt.color[0], 4);
        get(p, &pt.intensity, 2);
        p += 2;
    }
    return points;
}

namespace {

// A part file's header: magic, count, box, error, levels, content.
constexpr char kPartMagic[8] = {'S', 'G', 'P', 'A', 'R', 'T', '1', '\0'};
constexpr size_t kPartHeader = 8 + 8 + 48 + 8 + 4 + 4;

}  // namespace

std::string readFile(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error(file + ": cannot be opened: " + std::strerror(errno));
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) throw std::runtime_error(file + ": cannot be read");
    return s.str();
}

void writeFile(const std::string& file, const std::string& bytes) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(file + ": cannot be opened for writing: " + std::strerror(errno));
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error(file + ": cannot be written");
}

void appendRecords(const std::string& file, const std::vector<Point>& points) {
    std::ofstream out(file, std::ios::binary | std::ios::app);
    if (!out) throw std::runtime_error(file + ": cannot be opened for writing: " + std::strerror(errno));
    const std::string bytes = encode(points);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error(file + ": cannot be written");
}

std::vector<Point> readRecords(const std::string& file) {
    const std::string bytes = readFile(file);
    if (bytes.size() % kRecordBytes != 0)
        throw std::runtime_error(file + ": " + std::to_string(bytes.size()) + " bytes, not a whole number of records");
    return decodeRecords(bytes.data(), bytes.size() / kRecordBytes);
}

void writePart(const std::string& file, const TileMeta& meta, const std::vector<Point>& points) {
    std::string header(kPartHeader, '\0');
    char* p = header.data();
    const uint64_t count = points.size();
    const int32_t levels = meta.levels, content = meta.content ? 1 : 0;
    put(p, kPartMagic, 8);
    put(p, &count, 8);
    put(p, &meta.box.min[0], 24);
    put(p, &meta.box.max[0], 24);
    put(p, &meta.error, 8);
    put(p, &levels, 4);
    put(p, &content, 4);
    writeFile(file, header + encode(points));
}

std::vector<Point> readPart(const std::string& file, TileMeta& meta) {
    const std::string bytes = readFile(file);
    if (bytes.size() < kPartHeader || std::memcmp(bytes.data(), kPartMagic, 8) != 0)
        throw std::runtime_error(file + ": not a point part file (header)");
    const char* p = bytes.data() + 8;
    uint64_t count = 0;
    int32_t levels = 0, content = 0;
    get(p, &count, 8);
    get(p, &meta.box.min[0], 24);
    get(p, &meta.box.max[0], 24);
    get(p, &meta.error, 8);
    get(p, &levels, 4);
    get(p, &content, 4);
    // Checked by division: a count near 2^64 must not overflow the product.
    if ((bytes.size() - kPartHeader) % kRecordBytes != 0 || (bytes.size() - kPartHeader) / kRecordBytes != count)
        throw std::runtime_error(file + ": the header's count " + std::to_string(count) + " disagrees with its " +
                                 std::to_string(bytes.size()) + " bytes");
    if (levels < 1 || levels > kMaxLevel + 1 || !(meta.error > 0.0) || !std::isfinite(meta.error))
        throw std::runtime_error(file + ": bad levels or geometric error in the header");
    meta.levels = levels;
    meta.content = content != 0;
    return decodeRecords(p, size_t(count));
}

}  // namespace sg::pointtiles
