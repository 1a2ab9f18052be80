// openPly: the same points written as ascii, binary little and big endian PLY read back alike, in chunks and again
// after a rewind; property types converted; bad files refused with a LoadError naming the place and the reason.
#include "loaders/points/internal/ScanFormats.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

using namespace sg;
namespace fs = std::filesystem;

namespace {

struct Expected {
    float x, y, z;
    uint8_t r, g, b;
    uint16_t intensity;
    float nx, ny, nz;
};
// Values a float holds exactly.
const Expected kPoints[] = {{1.5f, -2.25f, 3.0f, 255, 128, 0, 1000, 0.0f, 0.0f, 1.0f},
                            {-0.5f, 0.75f, 1000.0f, 10, 20, 30, 0, 1.0f, 0.0f, 0.0f},
                            {100.25f, 200.5f, -300.125f, 0, 0, 255, 65535, 0.0f, 1.0f, 0.0f}};

// A `camera` element with a list before `vertex` (records: 7 [1 2 3], 8 []), a double after the vertex's known
// properties, and a `face` element with a list after it: all to be skipped.
std::string header(const std::string& format, int vertices = 3) {
    return "ply\nformat " + format +
           " 1.0\ncomment written by a test\nobj_info nothing\nelement camera 2\nproperty float a\n"
           "property list uchar int ids\nelement vertex " +
           std::to_string(vertices) +
           "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
           "property uchar blue\nproperty ushort intensity\nproperty float nx\nproperty float ny\nproperty float nz\n"
           "property double extra\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string ascii() {
    std::string s = header("ascii") + "7 3 1 2 3\n8 0\n";
    for (const Expected& p : kPoints)
        s += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + " " + std::to_string(p.r) +
             " " + std::to_string(p.g) + " " + std::to_string(p.b) + " " + std::to_string(p.intensity) + " " +
             std::to_string(p.nx) + " " + std::to_string(p.ny) + " " + std::to_string(p.nz) + " 42.5\n";
    return s + "3 0 1 2\n";
}

// Appends v's bytes in the byte order asked for.
struct Bytes {
    std::string data;
    bool big = false;
    template <class T>
    Bytes& operator<<(T v) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        const uint16_t one = 1;
        const bool hostBig = reinterpret_cast<const uint8_t*>(&one)[0] == 0;
        if (big != hostBig) std::reverse(b, b + sizeof(T));
        data.append(b, sizeof(T));
        return *this;
    }
};

std::string binary(bool big) {
    Bytes b;
    b.big = big;
    b.data = header(big ? "binary_big_endian" : "binary_little_endian");
    b << 7.0f << uint8_t(3) << int32_t(1) << int32_t(2) << int32_t(3) << 8.0f << uint8_t(0);
    for (const Expected& p : kPoints)
        b << p.x << p.y << p.z << p.r << p.g << p.b << p.intensity << p.nx << p.ny << p.nz << 42.5;
    b << uint8_t(3) << int32_t(0) << int32_t(1) << int32_t(2);
    return b.data;
}

std::string file(const std::string& name, const std::string& content) {
    const fs::path p = fs::temp_directory_path() / ("sgkit_ply_" + std::to_string(::getpid()) + "_" + name + ".ply");
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
}

std::vector<ScanPoint> readAll(ScanReader& r, size_t chunk) {
    std::vector<ScanPoint> all, part;
    while (r.read(part, chunk) > 0) all.insert(all.end(), part.begin(), part.end());
    return all;
}

// The LoadError reading the whole file gives ("" when none): its place (jsonPath) and what().
std::string failure(const std::string& content, std::string* place = nullptr) {
    const std::string path = file("bad", content);
    std::string what;
    try {
        auto r = openPly(path);
        readAll(*r, 2);
    } catch (const LoadError& e) {
        if (place) *place = e.jsonPath();
        what = e.what();
    }
    fs::remove(path);
    return what;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(PlyReadTest, AllThreeEncodingsGiveTheSamePointsInChunksAndAfterARewind) {
    const std::pair<std::string, std::string> files[] = {
        {"PLY ascii", ascii()}, {"PLY binary_little_endian", binary(false)}, {"PLY binary_big_endian", binary(true)}};
    for (const auto& [format, content] : files) {
        const std::string path = file("good", content);
        auto r = openPly(path);
        EXPECT_EQ(r->info().format, format);
        EXPECT_EQ(r->info().count, 3u);
        EXPECT_TRUE(r->info().hasColor && r->info().hasIntensity && r->info().hasNormal);
        std::vector<ScanPoint> part;
        EXPECT_EQ(r->read(part, 2), 2u) << format;
        EXPECT_EQ(r->read(part, 2), 1u) << format;
        EXPECT_EQ(r->read(part, 2), 0u) << format;
        r->rewind();
        const std::vector<ScanPoint> pts = readAll(*r, 100);
        ASSERT_EQ(pts.size(), 3u) << format;
        for (size_t i = 0; i < 3; ++i) {
            const Expected& e = kPoints[i];
            EXPECT_EQ(pts[i].position, dvec3(e.x, e.y, e.z)) << format << " " << i;
            EXPECT_EQ(pts[i].color, glm::u8vec4(e.r, e.g, e.b, 255)) << format << " " << i;
            EXPECT_EQ(pts[i].intensity, e.intensity) << format << " " << i;
            EXPECT_EQ(pts[i].normal, vec3(e.nx, e.ny, e.nz)) << format << " " << i;
        }
        r.reset();
        fs::remove(path);
    }
}

TEST(PlyReadTest, TypesAreConverted) {
    // Double, int and short positions; 16-bit colours to their high byte; a float alpha from 0..1; scalar_intensity.
    Bytes b;
    b.big = true;
    b.data =
        "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty double x\nproperty int y\n"
        "property short z\nproperty ushort red\nproperty ushort green\nproperty ushort blue\nproperty float alpha\n"
        "property float scalar_intensity\nend_header\n";
    b << 1e6 + 0.125 << int32_t(-5) << int16_t(7) << uint16_t(65535) << uint16_t(128 * 257) << uint16_t(257) << 0.5f
      << 12.0f;
    const std::string path = file("types", b.data);
    auto r = openPly(path);
    EXPECT_FALSE(r->info().hasNormal);
    const std::vector<ScanPoint> pts = readAll(*r, 10);
    ASSERT_EQ(pts.size(), 1u);
    EXPECT_EQ(pts[0].position, dvec3(1e6 + 0.125, -5.0, 7.0));
    EXPECT_EQ(pts[0].color, glm::u8vec4(255, 128, 1, 128));  // 0.5 x 255 = 127.5, rounded up
    EXPECT_EQ(pts[0].intensity, 12);
    EXPECT_EQ(pts[0].normal, vec3(0.0f));
    r.reset();
    fs::remove(path);
}

TEST(PlyReadTest, BadFilesNameThePlaceAndTheReason) {
    std::string place;
    // A header that lies: five vertices where the binary body holds three.
    std::string lying = binary(false);
    lying.replace(lying.find("element vertex 3"), 16, "element vertex 5");
    EXPECT_TRUE(has(failure(lying, &place), "do not fit")) << failure(lying);
    EXPECT_EQ(place.rfind("offset ", 0), 0u) << place;
    // The same in ascii: the body ends after three of five.
    std::string lyingText = ascii();
    lyingText.resize(lyingText.size() - 8);  // without the face's line, which would be read as a bad vertex
    lyingText.replace(lyingText.find("element vertex 3"), 16, "element vertex 5");
    EXPECT_TRUE(has(failure(lyingText, &place), "ends after 3")) << failure(lyingText);
    // A truncated body: the last vertex cut short (the face after it cut too).
    const std::string full = binary(false);
    EXPECT_TRUE(has(failure(full.substr(0, full.size() - 13 - 20)), "do not fit"));
    // A list before the vertices whose count runs past the data.
    std::string longList = binary(false);
    longList[header("binary_little_endian").size() + 4] = char(200);  // the camera's first list: 200 ints
    EXPECT_TRUE(has(failure(longList), "reaches past the file's end")) << failure(longList);
    // A position that is not finite, in ascii (point 1 is on line 26: 22 header lines, 2 camera lines) and in
    // binary (at the offset of its record).
    std::string nan = ascii();
    nan.replace(nan.find("-0.500000"), 9, "nan");
    EXPECT_TRUE(has(failure(nan, &place), "point 1 has a position that is not finite")) << failure(nan);
    EXPECT_EQ(place, "line 26");
    Bytes inf;
    inf.data =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n";
    const size_t start = inf.data.size();
    inf << 1.0f << 2.0f << 3.0f << 1.0f << std::numeric_limits<float>::infinity() << 3.0f;
    EXPECT_TRUE(has(failure(inf.data, &place), "point 1 has a position that is not finite"));
    EXPECT_EQ(place, "offset " + std::to_string(start + 12));
    // A token that is not a number.
    std::string token = ascii();
    token.replace(token.find("1.500000"), 8, "1.5x");
    EXPECT_TRUE(has(failure(token, &place), "\"1.5x\" is not a number")) << failure(token);
    EXPECT_EQ(place, "line 25");
    // Headers that are not PLY's or miss what a scan needs.
    EXPECT_TRUE(has(failure("plx\nformat ascii 1.0\nend_header\n"), "not a PLY file"));
    EXPECT_TRUE(has(failure("ply\nformat ascii 1.0\nelement face 0\nend_header\n"), "no vertex element"));
    EXPECT_TRUE(has(failure("ply\nformat ascii 1.0\nelement vertex 1\nproperty flot x\nend_header\n"), "unknown type"));
    EXPECT_TRUE(
        has(failure("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n"), "no x, y and z"));
    EXPECT_TRUE(has(failure("ply\nformat ascii 1.0\nelement vertex 1\n"), "no end_header"));
    EXPECT_TRUE(has(failure("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n"), "whole number"));
}
