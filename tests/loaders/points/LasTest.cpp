// LAS in and out: files of every point format and version written here byte by byte per the LAS 1.4 specification,
// read back through openScan; LasWriter's files read back; LAZ and malformed headers refused with their offset and
// reason; loadScan's node, thinning and point spacing.
#include "loaders/points/Scan.h"

#include "nodes/Geometry.h"
#include "nodes/Transform.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace sg;
using Data = std::vector<unsigned char>;

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_las_" + name; }

void writeFile(const std::string& path, const Data& d) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(d.data()), std::streamsize(d.size()));
}
Data readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Data(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template <class T>
void put(Data& d, size_t at, T v) {
    std::memcpy(&d[at], &v, sizeof v);
}

// A point as LAS stores it: integer coordinates, 16-bit intensity and colour.
struct RawPoint {
    int32_t x = 0, y = 0, z = 0;
    uint16_t intensity = 0, r = 0, g = 0, b = 0;
};

// A LAS file as the tests write it: the header of version 1.`minor`, no VLRs, the records right after the header.
struct Las {
    int minor = 2;
    uint8_t format = 0;
    uint16_t extraBytes = 0;  // appended to each record (filled with 0xab)
    double scale[3] = {0.01, 0.01, 0.001};
    double offset[3] = {500000.0, 4000000.0, 100.0};
    std::vector<RawPoint> points;
};

const uint16_t kHeaderSize[5] = {227, 227, 227, 235, 375};
const uint16_t kRecordLength[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
const uint16_t kRgbOffset[11] = {0, 0, 20, 28, 0, 28, 0, 30, 30, 0, 30};

Data lasBytes(const Las& las) {
    const size_t header = kHeaderSize[las.minor];
    const size_t length = kRecordLength[las.format] + las.extraBytes;
    Data d(header + length * las.points.size(), 0);
    std::memcpy(&d[0], "LASF", 4);
    d[24] = 1;
    d[25] = uint8_t(las.minor);
    put<uint16_t>(d, 94, uint16_t(header));
    put<uint32_t>(d, 96, uint32_t(header));
    d[104] = las.format;
    put<uint16_t>(d, 105, uint16_t(length));
    // LAS 1.4 leaves the legacy count 0 for formats 6-10 and gives the 64-bit one.
    put<uint32_t>(d, 107, las.minor == 4 && las.format >= 6 ? 0u : uint32_t(las.points.size()));
    if (las.minor == 4) put<uint64_t>(d, 247, las.points.size());
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (size_t i = 0; i < las.points.size(); ++i) {
        const RawPoint& p = las.points[i];
        const int32_t q[3] = {p.x, p.y, p.z};
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], q[c] * las.scale[c] + las.offset[c]);
            hi[c] = std::max(hi[c], q[c] * las.scale[c] + las.offset[c]);
        }
        const size_t at = header + i * length;
        std::memcpy(&d[at], q, 12);
        put<uint16_t>(d, at + 12, p.intensity);
        if (kRgbOffset[las.format]) {
            const uint16_t rgb[3] = {p.r, p.g, p.b};
            std::memcpy(&d[at + kRgbOffset[las.format]], rgb, 6);
        }
        std::memset(&d[at + kRecordLength[las.format]], 0xab, las.extraBytes);
    }
    for (int c = 0; c < 3; ++c) {
        put<double>(d, 131 + 8 * c, las.scale[c]);
        put<double>(d, 155 + 8 * c, las.offset[c]);
        put<double>(d, 179 + 16 * c, hi[c]);
        put<double>(d, 187 + 16 * c, lo[c]);
    }
    return d;
}

std::vector<ScanPoint> readAll(const std::string& path, ScanInfo* info = nullptr) {
    const std::unique_ptr<ScanReader> r = openScan(path);
    if (info) *info = r->info();
    std::vector<ScanPoint> all, chunk;
    while (r->read(chunk, 1000) > 0) all.insert(all.end(), chunk.begin(), chunk.end());
    return all;
}

// Points one by one: GCC 12 warns (falsely) of a null memmove on a vector assigned from a braced list.
std::vector<RawPoint> pointsOf(std::initializer_list<RawPoint> list) {
    std::vector<RawPoint> out;
    for (const RawPoint& p : list) out.push_back(p);
    return out;
}

// Two points whose values are worked out by hand below.
std::vector<RawPoint> twoPoints() {
    return pointsOf({{1000, -2000, 30000, 1234, 0xff00, 0x8000, 0x00ff}, {-1, 0, 7, 65535, 0x1234, 0xffff, 0}});
}

TEST(Las, EveryPointFormatOfEveryVersionReadsBack) {
    for (int format = 0; format <= 10; ++format) {
        // Formats 4 and 5 came with LAS 1.3, 6 to 10 with 1.4.
        for (int minor = format >= 6 ? 4 : format >= 4 ? 3 : 2; minor <= 4; ++minor) {
            SCOPED_TRACE("LAS 1." + std::to_string(minor) + " point format " + std::to_string(format));
            Las las;
            las.minor = minor;
            las.format = uint8_t(format);
            las.points = twoPoints();
            const std::string path = tempPath("formats.las");
            writeFile(path, lasBytes(las));
            ScanInfo info;
            const std::vector<ScanPoint> p = readAll(path, &info);
            EXPECT_EQ(info.format, "LAS 1." + std::to_string(minor) + " point format " + std::to_string(format));
            EXPECT_EQ(info.count, 2u);
            const bool rgb = format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
            EXPECT_EQ(info.hasColor, rgb);
            ASSERT_EQ(p.size(), 2u);
            // 1000 * 0.01 + 500000, -2000 * 0.01 + 4000000, 30000 * 0.001 + 100.
            EXPECT_NEAR(p[0].position.x, 500010.0, 1e-9);
            EXPECT_NEAR(p[0].position.y, 3999980.0, 1e-9);
            EXPECT_NEAR(p[0].position.z, 130.0, 1e-9);
            EXPECT_NEAR(p[1].position.x, 499999.99, 1e-9);
            EXPECT_NEAR(p[1].position.z, 100.007, 1e-9);
            EXPECT_EQ(p[0].intensity, 1234);
            EXPECT_EQ(p[1].intensity, 65535);
            if (rgb) {
                EXPECT_EQ(p[0].color, glm::u8vec4(255, 128, 0, 255));  // the high bytes of 0xff00, 0x8000, 0x00ff
                EXPECT_EQ(p[1].color, glm::u8vec4(0x12, 255, 0, 255));
            } else {
                EXPECT_EQ(p[0].color, glm::u8vec4(255));
            }
            // The header's bounds.
            EXPECT_NEAR(info.bounds.min.x, 499999.99, 1e-9);
            EXPECT_NEAR(info.bounds.max.x, 500010.0, 1e-9);
            EXPECT_NEAR(info.bounds.max.z, 130.0, 1e-9);
        }
    }
}

TEST(Las, ExtraBytesAfterEachRecordAreSkipped) {
    Las las;
    las.format = 3;
    las.extraBytes = 7;
    las.points =
        pointsOf({{1, 2, 3, 10, 0x0100, 0x0200, 0x0300}, {4, 5, 6, 20, 0, 0, 0}, {7, 8, 9, 30, 0xfe00, 0, 0x0100}});
    const std::string path = tempPath("extra.las");
    writeFile(path, lasBytes(las));
    const std::vector<ScanPoint> p = readAll(path);
    ASSERT_EQ(p.size(), 3u);
    EXPECT_NEAR(p[2].position.x, 500000.07, 1e-9);
    EXPECT_NEAR(p[2].position.z, 100.009, 1e-9);
    EXPECT_EQ(p[2].intensity, 30);
    EXPECT_EQ(p[2].color, glm::u8vec4(254, 0, 1, 255));
    EXPECT_EQ(p[1].intensity, 20);
}

TEST(Las, ReadsInChunksAndRewinds) {
    Las las;
    for (int i = 0; i < 5; ++i) las.points.push_back({i, 0, 0, uint16_t(i), 0, 0, 0});
    const std::string path = tempPath("chunks.las");
    writeFile(path, lasBytes(las));
    const std::unique_ptr<ScanReader> r = openScan(path);
    std::vector<ScanPoint> chunk;
    EXPECT_EQ(r->read(chunk, 2), 2u);
    EXPECT_EQ(r->read(chunk, 2), 2u);
    EXPECT_EQ(r->read(chunk, 2), 1u);
    ASSERT_EQ(chunk.size(), 1u);
    EXPECT_EQ(chunk[0].intensity, 4);
    EXPECT_EQ(r->read(chunk, 2), 0u);
    r->rewind();
    EXPECT_EQ(r->read(chunk, 10), 5u);
    EXPECT_EQ(chunk[3].intensity, 3);
}

TEST(Las, Version14TakesThe64BitCountWhenTheLegacyOneIsZero) {
    Las las;
    las.minor = 4;
    las.format = 1;
    las.points = twoPoints();
    Data d = lasBytes(las);
    put<uint32_t>(d, 107, 0);
    const std::string path = tempPath("count64.las");
    writeFile(path, d);
    ScanInfo info;
    EXPECT_EQ(readAll(path, &info).size(), 2u);
    EXPECT_EQ(info.count, 2u);
}

TEST(Las, WriterRoundTripsWithinTheScale) {
    std::vector<ScanPoint> points(1000);
    for (int i = 0; i < 1000; ++i) {
        ScanPoint& p = points[size_t(i)];
        p.position = dvec3(651000.0 + i * 0.0371, 4200000.0 - i * 0.0123, 50.0 + std::sin(i) * 3.0);
        p.color = glm::u8vec4(uint8_t(i), uint8_t(i * 7), uint8_t(255 - i % 256), 255);
        p.intensity = uint16_t(i * 61);
    }
    const std::string path = tempPath("written.las");
    for (int pass = 0; pass < 2; ++pass) {
        LasWriter w(pass == 0 ? path : path + "2", 0.001);
        w.setOrigin(dvec3(651000.0, 4200000.0, 0.0));
        w.write(std::vector<ScanPoint>(points.begin(), points.begin() + 400));
        w.write(std::vector<ScanPoint>(points.begin() + 400, points.end()));
        w.close();
    }
    EXPECT_EQ(readFile(path), readFile(path + "2"));  // no date or other varying bytes
    const Data bytes = readFile(path);
    ASSERT_GE(bytes.size(), 375u + 1000u * 36u);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(&bytes[26]), 5), "sgkit");
    EXPECT_EQ(bytes[90] | bytes[91] | bytes[92] | bytes[93], 0);  // creation day and year

    ScanInfo info;
    const std::vector<ScanPoint> back = readAll(path, &info);
    EXPECT_EQ(info.format, "LAS 1.4 point format 7");
    EXPECT_EQ(info.count, 1000u);
    ASSERT_EQ(back.size(), 1000u);
    for (size_t i = 0; i < back.size(); ++i) {
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[i].position[c], points[i].position[c], 0.0005 + 1e-9) << i;
        EXPECT_EQ(back[i].color, points[i].color) << i;  // x 257 then >> 8
        EXPECT_EQ(back[i].intensity, points[i].intensity) << i;
        EXPECT_TRUE(info.bounds.contains(back[i].position)) << i;
    }
    EXPECT_NEAR(info.bounds.min.x, 651000.0, 1e-9);
    EXPECT_NEAR(info.bounds.max.x, 651000.0 + 999 * 0.0371, 0.0005 + 1e-9);
}

TEST(Las, WriterRefusesAPointTheScaleCannotStore) {
    LasWriter w(tempPath("far.las"), 0.001);
    ScanPoint p;
    p.position = dvec3(1e7, 0.0, 0.0);  // 1e10 units: past 2^31
    EXPECT_THROW(w.write({p}), std::invalid_argument);
}

// The reason of the LoadError that reading `d` throws, and its offset ("offset N").
std::pair<std::string, std::string> refusal(const Data& d, const std::string& name = "bad.las") {
    const std::string path = tempPath(name);
    writeFile(path, d);
    try {
        readAll(path);
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), path);
        return {e.jsonPath(), e.reason()};
    }
    ADD_FAILURE() << "read " << name;
    return {};
}

Las validLas() {
    Las las;
    las.points = twoPoints();
    return las;
}

TEST(Las, LazIsRefusedWithHowToConvertIt) {
    Data d = lasBytes(validLas());
    d[104] = 0x80 | 3;  // LASzip marks compressed records with bit 7 of the point format
    auto [at, reason] = refusal(d);
    EXPECT_EQ(at, "offset 104");
    EXPECT_NE(reason.find("LAZ (compressed LAS) is not read"), std::string::npos) << reason;
    EXPECT_NE(reason.find("las2las -i in.laz -o out.las"), std::string::npos) << reason;
    EXPECT_NE(reason.find("pdal translate in.laz out.las"), std::string::npos) << reason;
    // A .laz name alone is refused too.
    EXPECT_NE(refusal(lasBytes(validLas()), "named.laz").second.find("LAZ"), std::string::npos);
}

TEST(Las, MalformedHeadersAreRefusedWithTheirOffsetAndReason) {
    const Data good = lasBytes(validLas());
    struct Case {
        const char* what;
        std::function<void(Data&)> spoil;
        const char* offset;
        const char* reason;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<Case> cases = {
        {"truncated", [](Data& d) { d.resize(100); }, "offset 0", "truncated"},
        {"count past the end", [](Data& d) { put<uint32_t>(d, 107, 3); }, "offset 107", "past the end"},
        {"short records", [](Data& d) { put<uint16_t>(d, 105, 19); }, "offset 105", "smaller than point format 0"},
        {"data past the end", [](Data& d) { put<uint32_t>(d, 96, uint32_t(d.size() + 1)); }, "offset 96",
         "outside the file"},
        {"NaN scale", [&](Data& d) { put<double>(d, 139, nan); }, "offset 139", "scale factor"},
        {"infinite offset", [&](Data& d) { put<double>(d, 163, inf); }, "offset 163", "not finite"},
        {"huge scale", [](Data& d) { put<double>(d, 131, 1e300); }, "offset 131", "infinite"},
        {"version 2.0", [](Data& d) { d[24] = 2, d[25] = 0; }, "offset 24", "LAS version 2.0"},
        {"point format 11", [](Data& d) { d[104] = 11; }, "offset 104", "point format 11"},
        {"header size", [](Data& d) { put<uint16_t>(d, 94, 200); }, "offset 94", "smaller than LAS 1.2"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        Data d = good;
        c.spoil(d);
        auto [at, reason] = refusal(d);
        EXPECT_EQ(at, c.offset) << reason;
        EXPECT_NE(reason.find(c.reason), std::string::npos) << reason;
    }
}

TEST(Las, OtherFilesAreNotScans) {
    const Data d = {'n', 'o', 't', ' ', 'a', ' ', 's', 'c', 'a', 'n'};
    EXPECT_NE(refusal(d, "other.bin").second.find("not a scan"), std::string::npos);
}

// loadScan's node: a Transform at the bounds' centre over one Geometry of points.
const Mesh& scanMesh(const ref_ptr<Node>& node, dvec3* centre = nullptr) {
    EXPECT_EQ(node->kind(), NodeKind::Transform);
    if (centre) *centre = static_cast<const Transform&>(*node).translation();
    const Node* g = node->child(0);
    EXPECT_EQ(g->kind(), NodeKind::Geometry);
    return *static_cast<const Geometry*>(g)->mesh();
}

TEST(Las, LoadScanCentresThePointsAndEstimatesTheirSpacing) {
    // A flat 10 x 10 square (scale 1, offset 0): spacing sqrt(100 / 4) = 5.
    Las flat;
    flat.scale[0] = flat.scale[1] = flat.scale[2] = 1.0;
    flat.offset[0] = flat.offset[1] = flat.offset[2] = 0.0;
    flat.format = 2;
    flat.points =
        pointsOf({{0, 0, 5, 1, 0xff00, 0, 0}, {10, 0, 5, 2, 0, 0, 0}, {0, 10, 5, 3, 0, 0, 0}, {10, 10, 5, 4, 0, 0, 0}});
    writeFile(tempPath("flat.las"), lasBytes(flat));
    dvec3 centre;
    const ref_ptr<Node> flatNode = loadScan(tempPath("flat.las"));  // holds the mesh
    const Mesh& m = scanMesh(flatNode, &centre);
    EXPECT_EQ(centre, dvec3(5.0, 5.0, 5.0));
    EXPECT_EQ(m.primitive(), Primitive::Points);
    ASSERT_EQ(m.pointCount(), 4u);
    EXPECT_EQ(m.positions()[0], vec3(-5.0f, -5.0f, 0.0f));
    EXPECT_EQ(m.positions()[3], vec3(5.0f, 5.0f, 0.0f));
    ASSERT_EQ(m.colors().size(), 4u);
    EXPECT_EQ(m.colors()[0], vec4(1.0f, 0.0f, 0.0f, 1.0f));
    ASSERT_EQ(m.intensities().size(), 4u);
    EXPECT_EQ(m.intensities()[2], 3);
    EXPECT_FLOAT_EQ(m.pointSpacing(), 5.0f);

    // The corners of a 2 x 2 x 2 cube: spacing (8 / 8)^(1/3) = 1.
    Las cube = flat;
    cube.points.clear();
    for (int i = 0; i < 8; ++i) cube.points.push_back({(i & 1) * 2, (i >> 1 & 1) * 2, (i >> 2) * 2, 0, 0, 0, 0});
    writeFile(tempPath("cube.las"), lasBytes(cube));
    EXPECT_FLOAT_EQ(scanMesh(loadScan(tempPath("cube.las"))).pointSpacing(), 1.0f);
}

TEST(Las, LoadScanThinsEvenlyToMaxPoints) {
    Las las;
    for (int i = 0; i < 10; ++i) las.points.push_back({i, 0, 0, uint16_t(i), 0, 0, 0});
    writeFile(tempPath("thin.las"), lasBytes(las));
    ScanLoadOptions options;
    options.maxPoints = 3;
    const ref_ptr<Node> thinNode = loadScan(tempPath("thin.las"), options);  // holds the mesh
    const Mesh& m = scanMesh(thinNode);
    ASSERT_EQ(m.pointCount(), 3u);
    // Point i is kept when (i + 1) * 3 / 10 passes an integer: points 3, 6 and 9.
    EXPECT_EQ(m.intensities(), (std::vector<uint16_t>{3, 6, 9}));
}

TEST(Las, AnEmptyScanIsALoadError) {
    Las las;
    writeFile(tempPath("empty.las"), lasBytes(las));
    try {
        loadScan(tempPath("empty.las"));
        ADD_FAILURE() << "loaded an empty scan";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.reason(), "no points");
    }
}

}  // namespace
