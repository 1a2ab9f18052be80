// The 3D Tiles binary formats: tiles written here byte by byte per the spec, each field read back, each
// malformation refused with its place and reason; and files converted by CesiumGS' 3d-tiles-tools.
#include "OutsideTools.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/internal/TileFormats.h"
#include "sg/cull/CullTraversal.h"

#include "nodes/Geometry.h"
#include "nodes/Group.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace {

using namespace sg;
using namespace sg::tiles;
using Data = std::vector<unsigned char>;

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_tiles_" + name; }

Data readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Data(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
void writeFile(const std::string& path, const Data& d) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(d.data()), std::streamsize(d.size()));
}

// A real glb: one triangle written by sg::saveGltf.
const Data& triangleGlb() {
    static const Data glb = [] {
        auto mesh = make<Mesh>();
        mesh->set({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}, {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)},
                  {0, 1, 2});
        auto root = make<Group>();
        root->addChild(make<Geometry>(mesh, make<Material>(vec4(1.0f))));
        const std::string path = tempPath("triangle.glb");
        saveGltf(*root, path);
        return readFile(path);
    }();
    return glb;
}

// Little-endian binary bodies.
struct Bin {
    Data d;
    Bin& u32(uint32_t v) {
        for (int i = 0; i < 4; ++i) d.push_back((v >> (8 * i)) & 0xff);
        return *this;
    }
    Bin& u16(uint16_t v) {
        d.push_back(v & 0xff);
        d.push_back(v >> 8);
        return *this;
    }
    Bin& f32(float f) {
        uint32_t u;
        std::memcpy(&u, &f, 4);
        return u32(u);
    }
    Bin& vec(float x, float y, float z) { return f32(x).f32(y).f32(z); }
};

void append(Data& d, const Data& more) { d.insert(d.end(), more.begin(), more.end()); }
void append(Data& d, const std::string& s) { d.insert(d.end(), s.begin(), s.end()); }
void pad(Data& d, unsigned char with) {
    while (d.size() % 8) d.push_back(with);
}

// A b3dm, i3dm (gltfFormat >= 0) or pnts tile laid out per the spec: feature table JSON padded with spaces so
// the binary starts on 8 bytes, each binary padded to 8 bytes, the tile padded to 8 bytes with zeros.
struct Tile {
    std::string magic = "b3dm";
    std::string featureJson = "{}";
    Data featureBin;
    std::string batchJson;
    Data batchBin;
    Data body;
    int gltfFormat = -1;  // i3dm only

    Data bytes() const {
        const size_t header = magic == "i3dm" ? 32 : 28;
        Data ftJson(header, 0);
        append(ftJson, featureJson);
        pad(ftJson, ' ');
        ftJson.erase(ftJson.begin(), ftJson.begin() + long(header));
        Data ftBin = featureBin, btJson, btBin = batchBin;
        pad(ftBin, 0);
        if (!batchJson.empty()) {
            append(btJson, batchJson);
            while ((header + ftJson.size() + ftBin.size() + btJson.size()) % 8) btJson.push_back(' ');
        }
        pad(btBin, 0);
        Data d;
        append(d, magic);
        Bin h;
        h.u32(1).u32(0).u32(uint32_t(ftJson.size())).u32(uint32_t(ftBin.size())).u32(uint32_t(btJson.size()));
        h.u32(uint32_t(btBin.size()));
        if (gltfFormat >= 0) h.u32(uint32_t(gltfFormat));
        append(d, h.d);
        for (const Data* part : std::initializer_list<const Data*>{&ftJson, &ftBin, &btJson, &btBin, &body})
            append(d, *part);
        pad(d, 0);
        setU32(d, 8, uint32_t(d.size()));
        return d;
    }
    static void setU32(Data& d, size_t at, uint32_t v) {
        for (int i = 0; i < 4; ++i) d[at + i] = (v >> (8 * i)) & 0xff;
    }
};

Data cmpt(const std::vector<Data>& tiles) {
    Data d;
    append(d, std::string("cmpt"));
    append(d, Bin().u32(1).u32(0).u32(uint32_t(tiles.size())).d);
    for (const Data& t : tiles) append(d, t);
    Tile::setU32(d, 8, uint32_t(d.size()));
    return d;
}

Tile i3dm(const std::string& featureJson, const Data& featureBin) {
    Tile t;
    t.magic = "i3dm";
    t.gltfFormat = 1;
    t.featureJson = featureJson;
    t.featureBin = featureBin;
    t.body = triangleGlb();
    return t;
}

B3dm b3dm(const Data& d) { return parseB3dm("t.b3dm", d.data(), d.size()); }
I3dm i3dmOf(const Data& d) { return parseI3dm("t.i3dm", d.data(), d.size()); }

// A LoadError at `path` whose reason holds `reason`.
void expectError(const std::function<void()>& f, const std::string& path, const std::string& reason) {
    try {
        f();
        ADD_FAILURE() << "no LoadError; expected " << path << ": " << reason;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath(), path) << e.what();
        EXPECT_NE(e.reason().find(reason), std::string::npos) << "reason: " << e.reason();
    }
}
void expectB3dmError(const Data& d, const std::string& path, const std::string& reason) {
    expectError([&] { b3dm(d); }, path, reason);
}
void expectI3dmError(const Data& d, const std::string& path, const std::string& reason) {
    expectError([&] { i3dmOf(d); }, path, reason);
}
void expectCmptError(const Data& d, const std::string& path, const std::string& reason) {
    expectError([&] { parseCmpt("t.cmpt", d.data(), d.size()); }, path, reason);
}

void expectVec(const dvec3& got, const dvec3& want, double tol = 1e-9) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], tol) << "component " << k;
}
dvec3 column(const dmat4& m, int c) { return dvec3(m[c]); }

}  // namespace

TEST(TileFormats, SniffsByFirstBytes) {
    auto sniff = [](const std::string& s) {
        return sniffContent(reinterpret_cast<const unsigned char*>(s.data()), s.size());
    };
    EXPECT_EQ(sniff("glTF...."), ContentKind::Glb);
    EXPECT_EQ(sniff("b3dm"), ContentKind::B3dm);
    EXPECT_EQ(sniff("i3dm...."), ContentKind::I3dm);
    EXPECT_EQ(sniff("cmpt...."), ContentKind::Cmpt);
    EXPECT_EQ(sniff("pnts...."), ContentKind::Pnts);
    EXPECT_EQ(sniff("{\"asset\":{}}"), ContentKind::Json);
    EXPECT_EQ(sniff("\xEF\xBB\xBF \r\n\t{}"), ContentKind::Json);
    EXPECT_EQ(sniff("  [1]"), ContentKind::Unknown);
    EXPECT_EQ(sniff("b3d"), ContentKind::Unknown);
    EXPECT_EQ(sniff(""), ContentKind::Unknown);
    EXPECT_EQ(sniffContent(nullptr, 0), ContentKind::Unknown);
}

TEST(TileFormats, B3dmFields) {
    Tile t;
    t.featureJson = R"({"BATCH_LENGTH":5,"RTC_CENTER":[1.5,-2.25,6378137.125]})";
    t.batchJson = R"({"id":{"byteOffset":0,"componentType":"UNSIGNED_INT","type":"SCALAR"}})";
    t.batchBin = Bin().u32(1).u32(2).u32(3).u32(4).u32(5).d;
    t.body = triangleGlb();
    const Data d = t.bytes();
    const B3dm b = b3dm(d);
    EXPECT_EQ(b.batchLength, 5u);
    ASSERT_TRUE(b.hasRtcCenter);
    expectVec(b.rtcCenter, dvec3(1.5, -2.25, 6378137.125), 0.0);
    ASSERT_EQ(b.glb.size, triangleGlb().size());  // the glb's own length: the tile's padding is left out
    EXPECT_TRUE(std::equal(b.glb.data, b.glb.data + b.glb.size, triangleGlb().begin()));
    EXPECT_GE(b.glb.data, d.data());
    EXPECT_LE(b.glb.data + b.glb.size, d.data() + d.size());

    // Globals from the binary body; no RTC_CENTER.
    t.featureJson = R"({"BATCH_LENGTH":{"byteOffset":4}})";
    t.featureBin = Bin().u32(0).u32(42).d;
    const B3dm c = b3dm(t.bytes());
    EXPECT_EQ(c.batchLength, 42u);
    EXPECT_FALSE(c.hasRtcCenter);
    t.featureJson = R"({"BATCH_LENGTH":0,"RTC_CENTER":{"byteOffset":4}})";
    t.featureBin = Bin().u32(0).vec(10, 20, 30).d;
    expectVec(b3dm(t.bytes()).rtcCenter, dvec3(10, 20, 30), 0.0);
}

TEST(TileFormats, I3dmFloatPositionsNormalsAndScale) {
    // Two instances: positions relative to RTC_CENTER, up +x, right +y (so forward = right x up = -z),
    // uniform scales 2 and 3.
    Bin b;
    b.vec(1, 2, 3).vec(-4, 5, -6);  // POSITION at 0
    b.vec(1, 0, 0).vec(0, 0, 2);    // NORMAL_UP at 24 (the second not unit: normalized)
    b.vec(0, 1, 0).vec(1, 0, 0);    // NORMAL_RIGHT at 48
    b.f32(2).f32(3);                // SCALE at 72
    const I3dm r = i3dmOf(i3dm(R"({"INSTANCES_LENGTH":2,"RTC_CENTER":[100,200,300],"POSITION":{"byteOffset":0},
        "NORMAL_UP":{"byteOffset":24},"NORMAL_RIGHT":{"byteOffset":48},"SCALE":{"byteOffset":72}})",
                               b.d)
                              .bytes());
    ASSERT_EQ(r.instances.size(), 2u);
    EXPECT_TRUE(r.glbUri.empty());
    EXPECT_EQ(r.glb.size, triangleGlb().size());
    const dmat4& m0 = r.instances[0];
    expectVec(column(m0, 0), dvec3(0, 2, 0));   // right * 2
    expectVec(column(m0, 1), dvec3(2, 0, 0));   // up * 2
    expectVec(column(m0, 2), dvec3(0, 0, -2));  // cross(right, up) * 2
    expectVec(column(m0, 3), dvec3(101, 202, 303));
    EXPECT_EQ(m0[3][3], 1.0);
    const dmat4& m1 = r.instances[1];
    expectVec(column(m1, 0), dvec3(3, 0, 0));
    expectVec(column(m1, 1), dvec3(0, 0, 3));
    expectVec(column(m1, 2), dvec3(0, -3, 0));
    expectVec(column(m1, 3), dvec3(96, 205, 294));
}

TEST(TileFormats, I3dmQuantizedPositionsAndOctNormals) {
    // The spec's example: corners of a quantized volume from -250 to 250 in x and z, up +y and right +x
    // oct-encoded; and SCALE_NON_UNIFORM.
    Bin b;
    for (uint16_t q : {0, 0, 0, 65535, 0, 0, 0, 0, 65535, 65535, 0, 65535}) b.u16(q);  // POSITION_QUANTIZED at 0
    for (int i = 0; i < 4; ++i) b.u16(32768).u16(65535);                               // NORMAL_UP_OCT32P at 24
    for (int i = 0; i < 4; ++i) b.u16(65535).u16(32768);                               // NORMAL_RIGHT_OCT32P at 40
    for (int i = 0; i < 4; ++i) b.vec(1, 2, 0.5f);                                     // SCALE_NON_UNIFORM at 56
    const I3dm r = i3dmOf(i3dm(R"({"INSTANCES_LENGTH":4,"QUANTIZED_VOLUME_OFFSET":[-250.0,0.0,-250.0],
        "QUANTIZED_VOLUME_SCALE":[500.0,0.0,500.0],"POSITION_QUANTIZED":{"byteOffset":0},
        "NORMAL_UP_OCT32P":{"byteOffset":24},"NORMAL_RIGHT_OCT32P":{"byteOffset":40},
        "SCALE_NON_UNIFORM":{"byteOffset":56}})",
                               b.d)
                              .bytes());
    ASSERT_EQ(r.instances.size(), 4u);
    const dvec3 corners[4] = {{-250, 0, -250}, {250, 0, -250}, {-250, 0, 250}, {250, 0, 250}};
    for (int i = 0; i < 4; ++i) {
        SCOPED_TRACE(i);
        const dmat4& m = r.instances[size_t(i)];
        expectVec(column(m, 3), corners[i], 1e-9);
        expectVec(column(m, 0), dvec3(1, 0, 0), 1e-4);    // right, x scale 1
        expectVec(column(m, 1), dvec3(0, 2, 0), 2e-4);    // up, y scale 2
        expectVec(column(m, 2), dvec3(0, 0, 0.5), 1e-4);  // right x up = +z, z scale 0.5
    }
}

TEST(TileFormats, I3dmOctDecodingOfOtherDirections) {
    // -z folds onto the corners of the octahedron: (0, 0) and (65535, 65535) both decode to -z; up -x is (0, 32768).
    Bin b;
    b.vec(0, 0, 0);
    b.u16(0).u16(32768);  // up: -x
    b.u16(0).u16(0);      // right: -z
    const I3dm r = i3dmOf(i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0},
        "NORMAL_UP_OCT32P":{"byteOffset":12},"NORMAL_RIGHT_OCT32P":{"byteOffset":16}})",
                               b.d)
                              .bytes());
    expectVec(column(r.instances[0], 1), dvec3(-1, 0, 0), 1e-4);
    expectVec(column(r.instances[0], 0), dvec3(0, 0, -1), 1e-4);
    expectVec(column(r.instances[0], 2), dvec3(0, 1, 0), 1e-4);  // (0,0,-1) x (-1,0,0)
}

TEST(TileFormats, I3dmEastNorthUpAtAnEcefPosition) {
    // An instance on the WGS84 surface at latitude 45, longitude 30 (RTC_CENTER holds the ECEF position, as
    // float32 POSITION cannot); its rotation is east, north, up there.
    const double a = 6378137.0, e2 = 6.69437999014e-3, lat = glm::radians(45.0), lon = glm::radians(30.0);
    const double nRadius = a / std::sqrt(1 - e2 * std::sin(lat) * std::sin(lat));
    const dvec3 ecef(nRadius * std::cos(lat) * std::cos(lon), nRadius * std::cos(lat) * std::sin(lon),
                     nRadius * (1 - e2) * std::sin(lat));
    char json[256];
    std::snprintf(json, sizeof json,
                  R"({"INSTANCES_LENGTH":2,"RTC_CENTER":[%.17g,%.17g,%.17g],"POSITION":{"byteOffset":0},)"
                  R"("EAST_NORTH_UP":true})",
                  ecef.x, ecef.y, ecef.z);
    const I3dm r = i3dmOf(i3dm(json, Bin().vec(0, 0, 0).vec(0, 0, 0).d).bytes());
    ASSERT_EQ(r.instances.size(), 2u);
    const dmat4& m = r.instances[0];
    const dvec3 east = column(m, 0), north = column(m, 1), up = column(m, 2);
    // The geodetic normal (the ellipsoid's, not the direction from the centre).
    const dvec3 normal(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
    expectVec(up, normal, 1e-9);
    EXPECT_GT(glm::length(up - glm::normalize(ecef)), 1e-3);  // not the geocentric direction
    EXPECT_NEAR(east.z, 0.0, 1e-12);                          // east is horizontal
    expectVec(east, dvec3(-std::sin(lon), std::cos(lon), 0), 1e-9);
    expectVec(north, glm::cross(up, east), 1e-9);
    EXPECT_GT(north.z, 0.0);
    expectVec(column(m, 3), ecef, 1e-6);

    // On the polar axis (east undefined: a fixed frame) and at the largest coordinates, the frame stays orthonormal.
    for (const char* rtc : {"[0,0,-6356752.3]", "[0,0,0]", "[1e308,-1.7e308,1.79e308]", "[1e-300,0,1]"}) {
        SCOPED_TRACE(rtc);
        const I3dm e = i3dmOf(
            i3dm(
                std::string(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0},"EAST_NORTH_UP":true,"RTC_CENTER":)") +
                    rtc + "}",
                Bin().vec(0, 0, 0).d)
                .bytes());
        const glm::dmat3 rot(e.instances[0]);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(glm::length(rot[c]), 1.0, 1e-12) << c;
        expectVec(glm::cross(rot[0], rot[1]), rot[2], 1e-12);
        EXPECT_NEAR(glm::dot(rot[0], rot[1]), 0.0, 1e-12);
    }
    const I3dm south = i3dmOf(
        i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0},"EAST_NORTH_UP":true,"RTC_CENTER":[0,0,-6356752.3]})",
             Bin().vec(0, 0, 0).d)
            .bytes());
    expectVec(column(south.instances[0], 2), dvec3(0, 0, -1));  // up at the south pole

    // Explicit normals win over EAST_NORTH_UP; without either the rotation is the identity.
    const I3dm normals = i3dmOf(i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0},"EAST_NORTH_UP":true,
        "NORMAL_UP":{"byteOffset":12},"NORMAL_RIGHT":{"byteOffset":24}})",
                                     Bin().vec(6378137, 0, 0).vec(0, 0, 1).vec(1, 0, 0).d)
                                    .bytes());
    expectVec(column(normals.instances[0], 0), dvec3(1, 0, 0));
    expectVec(column(normals.instances[0], 1), dvec3(0, 0, 1));
    const I3dm plain =
        i3dmOf(i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0},"EAST_NORTH_UP":false})", Bin().vec(7, 8, 9).d)
                   .bytes());
    EXPECT_EQ(plain.instances[0], glm::translate(dmat4(1.0), dvec3(7, 8, 9)));
}

TEST(TileFormats, I3dmGltfUri) {
    Tile t = i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0}})", Bin().vec(0, 0, 0).d);
    t.gltfFormat = 0;
    t.body.clear();
    append(t.body, std::string("models/tree.glb   "));
    t.body.push_back(0);
    const Data d = t.bytes();  // padded further with NULs to 8 bytes
    const I3dm r = i3dmOf(d);
    EXPECT_EQ(r.glbUri, "models/tree.glb");
    EXPECT_EQ(r.glb.data, nullptr);
    EXPECT_EQ(r.glb.size, 0u);
    ASSERT_EQ(r.instances.size(), 1u);
}

TEST(TileFormats, CmptFlattensNestedComposites) {
    Tile b;
    b.featureJson = R"({"BATCH_LENGTH":0})";
    b.body = triangleGlb();
    const Data b3 = b.bytes();
    const Data i3 = i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0}})", Bin().vec(1, 2, 3).d).bytes();
    Tile p;
    p.magic = "pnts";
    p.featureJson = R"({"POINTS_LENGTH":2,"POSITION":{"byteOffset":0}})";
    p.featureBin = Bin().vec(0, 0, 0).vec(1, 1, 1).d;
    const Data pn = p.bytes();
    const Data d = cmpt({b3, cmpt({i3, cmpt({pn})}), b3});
    const Cmpt c = parseCmpt("t.cmpt", d.data(), d.size());
    ASSERT_EQ(c.tiles.size(), 4u);
    const Data* want[4] = {&b3, &i3, &pn, &b3};
    const size_t offsets[4] = {16, 16 + b3.size() + 16, 16 + b3.size() + 16 + i3.size() + 16,
                               16 + b3.size() + 16 + i3.size() + 16 + pn.size()};
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(c.tiles[size_t(i)].data, d.data() + offsets[i]) << i;
        ASSERT_EQ(c.tiles[size_t(i)].size, want[i]->size()) << i;
    }
    EXPECT_EQ(parseB3dm("inner", c.tiles[0].data, c.tiles[0].size).glb.size, triangleGlb().size());
    expectVec(column(parseI3dm("inner", c.tiles[1].data, c.tiles[1].size).instances.at(0), 3), dvec3(1, 2, 3));
    EXPECT_EQ(pntsPointCount("inner", c.tiles[2].data, c.tiles[2].size), 2u);

    const Data empty = cmpt({});
    EXPECT_TRUE(parseCmpt("e", empty.data(), empty.size()).tiles.empty());
}

TEST(TileFormats, CmptNestingDepth) {
    Data d = i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0}})", Bin().vec(1, 2, 3).d).bytes();
    for (int i = 0; i < 8; ++i) d = cmpt({d});
    EXPECT_EQ(parseCmpt("eight", d.data(), d.size()).tiles.size(), 1u);
    d = cmpt({d});
    expectCmptError(d, "tiles[0].tiles[0].tiles[0].tiles[0].tiles[0].tiles[0].tiles[0].tiles[0]",
                    "nested deeper than 8");
}

TEST(TileFormats, CmptMalformed) {
    Tile b;
    b.featureJson = R"({"BATCH_LENGTH":0})";
    b.body = triangleGlb();
    const Data b3 = b.bytes();
    Data unknown = b3;
    std::memcpy(unknown.data(), "vctr", 4);
    expectCmptError(cmpt({b3, b3, unknown}), "tiles[2].header.magic", "unknown tile format 'vctr'");

    Data d = cmpt({b3, b3});
    Tile::setU32(d, 16 + b3.size() + 8, uint32_t(b3.size() + 8));  // the second claims 8 bytes more than there are
    expectCmptError(d, "tiles[1].header.byteLength", "outside [12, " + std::to_string(b3.size()) + "]");
    d = cmpt({b3});
    Tile::setU32(d, 12, 1000000);  // tilesLength far past the tiles present
    expectCmptError(d, "tiles[1]", "no room for its 12-byte header");
    d = cmpt({b3});
    Tile::setU32(d, 16 + 8, 4);
    expectCmptError(d, "tiles[0].header.byteLength", "outside [12,");
    d = cmpt({cmpt({b3})});
    Tile::setU32(d, 16 + 4, 2);  // the inner composite's version
    expectCmptError(d, "tiles[0].header.version", "version 2");
    d = cmpt({b3});
    expectCmptError(Data(d.begin(), d.begin() + 10), "header", "shorter than the 16-byte cmpt header");
    d.push_back(0);
    expectCmptError(d, "header.byteLength", "disagrees");
}

TEST(TileFormats, PntsPointCount) {
    Tile p;
    p.magic = "pnts";
    p.featureJson = R"({"POINTS_LENGTH":3,"POSITION":{"byteOffset":0}})";
    p.featureBin = Bin().vec(0, 0, 0).vec(1, 1, 1).vec(2, 2, 2).d;
    Data d = p.bytes();
    EXPECT_EQ(pntsPointCount("p", d.data(), d.size()), 3u);
    p.featureJson = R"({"POSITION":{"byteOffset":0}})";
    d = p.bytes();
    expectError([&] { pntsPointCount("p", d.data(), d.size()); }, "featureTable.POINTS_LENGTH", "missing");
    p.featureJson = R"({"POINTS_LENGTH":-3})";
    d = p.bytes();
    expectError([&] { pntsPointCount("p", d.data(), d.size()); }, "featureTable.POINTS_LENGTH", "integer");
}

TEST(TileFormats, HeaderMalformations) {
    Tile t;
    t.featureJson = R"({"BATCH_LENGTH":0})";
    t.body = triangleGlb();
    const Data good = t.bytes();
    ASSERT_NO_THROW(b3dm(good));

    expectB3dmError(Data(good.begin(), good.begin() + 20), "header", "shorter than the 28-byte b3dm header");
    expectB3dmError(Data(), "header", "0 bytes");
    Data d = good;
    d.insert(d.end(), 8, 0);
    expectB3dmError(d, "header.byteLength", "disagrees");
    d = good;
    Tile::setU32(d, 4, 2);
    expectB3dmError(d, "header.version", "version 2 (only 1)");
    d = good;
    std::memcpy(d.data(), "i3dm", 4);
    expectB3dmError(d, "header.magic", "not 'b3dm'");
    // Chunk lengths past the end, including ones whose sum would wrap a 32-bit offset.
    d = good;
    Tile::setU32(d, 16, 0xfffffff8u);
    expectB3dmError(d, "header.featureTableBinaryByteLength", "exceed");
    d = good;
    Tile::setU32(d, 12, uint32_t(good.size()));
    expectB3dmError(d, "header.featureTableJSONByteLength", "exceed");
    d = good;
    Tile::setU32(d, 20, 0x21ffffffu);  // just under the legacy test
    expectB3dmError(d, "header.batchTableJSONByteLength", "exceed");
    d = good;
    Tile::setU32(d, 24, uint32_t(good.size()));
    expectB3dmError(d, "header.batchTableBinaryByteLength", "exceed");
    // No glb after the tables, or something else there.
    Tile noGlb = t;
    noGlb.body.clear();
    expectB3dmError(noGlb.bytes(), "glb", "under its 12-byte header");
    noGlb.body = Data(16, 'x');
    expectB3dmError(noGlb.bytes(), "glb", "not 'glTF'");
    // The glb's own length past the end of the tile.
    d = good;
    const size_t glbAt =
        size_t(std::search(d.begin(), d.end(), triangleGlb().begin(), triangleGlb().end()) - d.begin());
    ASSERT_LT(glbAt, d.size());
    Tile::setU32(d, glbAt + 8, uint32_t(d.size() - glbAt + 1));
    expectB3dmError(d, "glb", "length " + std::to_string(d.size() - glbAt + 1) + " is outside [12, ");
}

TEST(TileFormats, LegacyB3dmHeadersAreRefusedByName) {
    const Data& glb = triangleGlb();
    // Legacy 1: magic, version, byteLength, batchLength, batchTableByteLength (20 bytes), then the glb.
    Data d;
    append(d, std::string("b3dm"));
    append(d, Bin().u32(1).u32(0).u32(0).u32(0).d);
    append(d, glb);
    Tile::setU32(d, 8, uint32_t(d.size()));
    expectB3dmError(d, "header", "legacy b3dm header [batchLength] [batchTableByteLength]");
    // Legacy 2: magic, version, byteLength, batchTableJsonByteLength, batchTableBinaryByteLength, batchLength
    // (24 bytes), then the batch table and the glb.
    const std::string batch = R"({"id":[7]})";
    d.clear();
    append(d, std::string("b3dm"));
    append(d, Bin().u32(1).u32(0).u32(uint32_t(batch.size())).u32(0).u32(1).d);
    append(d, batch);
    append(d, glb);
    Tile::setU32(d, 8, uint32_t(d.size()));
    expectB3dmError(d, "header", "legacy b3dm header [batchTableJsonByteLength] [batchTableBinaryByteLength]");
}

TEST(TileFormats, FeatureTableMalformations) {
    Tile t;
    t.body = triangleGlb();
    auto withJson = [&](const std::string& json, const Data& bin = {}) {
        t.featureJson = json;
        t.featureBin = bin;
        return t.bytes();
    };
    expectB3dmError(withJson("[1,2]"), "featureTable", "not an object");
    expectB3dmError(withJson(R"("BATCH_LENGTH")"), "featureTable", "not an object");
    expectB3dmError(withJson(R"({"BATCH_LENGTH":0)"), "featureTable", "JSON: ");
    expectB3dmError(withJson(std::string(100, '[') + std::string(100, ']')), "featureTable", "nested deeper than 64");
    expectB3dmError(withJson(R"({"BATCH_LENGTH":"5"})"), "featureTable.BATCH_LENGTH", "integer");
    expectB3dmError(withJson(R"({"BATCH_LENGTH":4294967296})"), "featureTable.BATCH_LENGTH", "integer in [0, 2^32)");
    expectB3dmError(withJson(R"({"BATCH_LENGTH":1.5})"), "featureTable.BATCH_LENGTH", "integer");
    expectB3dmError(withJson(R"({"RTC_CENTER":[1,2]})"), "featureTable.RTC_CENTER", "array of 3 numbers");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"x":1}})"), "featureTable.RTC_CENTER.byteOffset", "missing");
    expectB3dmError(withJson(R"({"RTC_CENTER":[1,"2",3]})"), "featureTable.RTC_CENTER", "element 1 is not a number");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"byteOffset":0}})", Bin().vec(1, NAN, 3).d), "featureTable.RTC_CENTER",
                    "element 1 is not finite");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"byteOffset":0}})", Bin().vec(1, 2, INFINITY).d),
                    "featureTable.RTC_CENTER", "element 2 is not finite");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"byteOffset":8}})", Bin().vec(1, 2, 3).d), "featureTable.RTC_CENTER",
                    "past the end of the feature table binary (16 bytes)");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"byteOffset":2}})", Bin().vec(1, 2, 3).d),
                    "featureTable.RTC_CENTER.byteOffset", "not a multiple of the component size 4");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"byteOffset":-4}})", Bin().vec(1, 2, 3).d),
                    "featureTable.RTC_CENTER.byteOffset", "non-negative integer");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"byteOffset":18446744073709551612}})", Bin().vec(1, 2, 3).d),
                    "featureTable.RTC_CENTER", "past the end");
    expectB3dmError(withJson(R"({"RTC_CENTER":{"byteOffset":0,"componentType":"DOUBLE"}})", Bin().vec(1, 2, 3).d),
                    "featureTable.RTC_CENTER.componentType", "must be FLOAT");
}

TEST(TileFormats, I3dmMalformations) {
    const Data pos2 = Bin().vec(1, 2, 3).vec(4, 5, 6).d;
    auto tile = [](const std::string& json, const Data& bin) { return i3dm(json, bin).bytes(); };
    expectI3dmError(tile(R"({"POSITION":{"byteOffset":0}})", pos2), "featureTable.INSTANCES_LENGTH",
                    "missing (required)");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":[2],"POSITION":{"byteOffset":0}})", pos2),
                    "featureTable.INSTANCES_LENGTH", "integer");
    // More instances than the arrays hold.
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":3,"POSITION":{"byteOffset":0}})", pos2), "featureTable.POSITION",
                    "3 elements of 12 bytes is past the end of the feature table binary (24 bytes)");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":4000000000,"POSITION":{"byteOffset":0}})", pos2),
                    "featureTable.POSITION", "past the end");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":4},"SCALE":{"byteOffset":0}})", pos2),
                    "featureTable.POSITION", "past the end");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2})", pos2), "featureTable.POSITION",
                    "neither POSITION nor POSITION_QUANTIZED");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":1,"POSITION":[1,2,3]})", pos2), "featureTable.POSITION",
                    "must refer to the binary body");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":2}})", pos2),
                    "featureTable.POSITION.byteOffset", "not a multiple of the component size 4");
    expectI3dmError(
        tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0,"componentType":"UNSIGNED_SHORT"}})", pos2),
        "featureTable.POSITION.componentType", "must be FLOAT");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0}})", Bin().vec(1, 2, 3).vec(4, NAN, 6).d),
                    "featureTable.POSITION", "instance 1: not finite");
    // Quantized positions need the volume; odd offsets of uint16 data are refused, even ones are fine.
    const Data q = Bin().u16(1).u16(2).u16(3).u16(4).d;
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":1,"POSITION_QUANTIZED":{"byteOffset":0},
        "QUANTIZED_VOLUME_OFFSET":[0,0,0]})",
                         q),
                    "featureTable.QUANTIZED_VOLUME_SCALE", "POSITION_QUANTIZED needs it");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":1,"POSITION_QUANTIZED":{"byteOffset":1},
        "QUANTIZED_VOLUME_OFFSET":[0,0,0],"QUANTIZED_VOLUME_SCALE":[1,1,1]})",
                         q),
                    "featureTable.POSITION_QUANTIZED.byteOffset", "multiple of the component size 2");
    EXPECT_NO_THROW(i3dmOf(tile(R"({"INSTANCES_LENGTH":1,"POSITION_QUANTIZED":{"byteOffset":2},
        "QUANTIZED_VOLUME_OFFSET":[0,0,0],"QUANTIZED_VOLUME_SCALE":[1,1,1]})",
                                q)));
    // Normals: zero length, parallel, one of a pair missing.
    Data bin = pos2;
    append(bin, Bin().vec(0, 1, 0).vec(0, 0, 0).vec(1, 0, 0).vec(1, 0, 0).d);  // up at 24, right at 48
    const std::string normals = R"("NORMAL_UP":{"byteOffset":24},"NORMAL_RIGHT":{"byteOffset":48})";
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},)" + normals + "}", bin),
                    "featureTable.NORMAL_UP", "instance 1: zero-length or non-finite up normal");
    bin = pos2;
    append(bin, Bin().vec(0, 1, 0).vec(0, 1, 0).vec(1, 0, 0).vec(0, -3, 0).d);
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},)" + normals + "}", bin),
                    "featureTable.NORMAL_UP", "instance 1: the up and right normals are parallel");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},"NORMAL_UP":{"byteOffset":0}})", pos2),
                    "featureTable.NORMAL_RIGHT", "missing");
    expectI3dmError(
        tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},"NORMAL_RIGHT_OCT32P":{"byteOffset":0}})", pos2),
        "featureTable.NORMAL_UP_OCT32P", "missing");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},"EAST_NORTH_UP":1})", pos2),
                    "featureTable.EAST_NORTH_UP", "true or false");
    // Scales and batch ids.
    bin = pos2;
    append(bin, Bin().f32(1).f32(NAN).d);
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},"SCALE":{"byteOffset":24}})", bin),
                    "featureTable.SCALE", "instance 1: not finite");
    expectI3dmError(
        tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},"SCALE_NON_UNIFORM":{"byteOffset":12}})", pos2),
        "featureTable.SCALE_NON_UNIFORM", "past the end");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},
        "BATCH_ID":{"byteOffset":0,"componentType":"FLOAT"}})",
                         pos2),
                    "featureTable.BATCH_ID.componentType", "UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    expectI3dmError(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},
        "BATCH_ID":{"byteOffset":20,"componentType":"UNSIGNED_INT"}})",
                         pos2),
                    "featureTable.BATCH_ID", "past the end");
    EXPECT_NO_THROW(i3dmOf(tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},
        "BATCH_ID":{"byteOffset":20}})",
                                pos2)));  // uint16 by default: 20 + 2 * 2 fits in 24
    // The header's gltfFormat and the URI.
    Data d = tile(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0}})", pos2);
    Tile::setU32(d, 28, 2);
    expectI3dmError(d, "header.gltfFormat", "gltfFormat 2");
    Tile t = i3dm(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0}})", pos2);
    t.gltfFormat = 0;
    t.body = Data(5, ' ');
    expectI3dmError(t.bytes(), "glbUri", "empty glTF URI");
    expectI3dmError(Data(d.begin(), d.begin() + 30), "header", "shorter than the 32-byte i3dm header");
}

// Interoperation with CesiumGS' 3d-tiles-tools (npm, fetched by the tiles-tools target): its tiles parse here,
// and it reads back the glb of tiles written by this test's writer.
namespace {

#ifdef SGKIT_TILES_TOOLS
const std::string kTool = SGKIT_TILES_TOOLS;
#else
const std::string kTool;
#endif

bool haveTool() { return !kTool.empty() && std::ifstream(kTool).good(); }

// Runs `3d-tiles-tools <args>`; its output goes to a log that a failure shows.
void tool(const std::string& args) {
    const std::string log = tempPath("tool.log");
    const int rc = std::system(("\"" + kTool + "\" " + args + " -f --logLevel warn >\"" + log + "\" 2>&1").c_str());
    const Data out = readFile(log);
    ASSERT_EQ(rc, 0) << "3d-tiles-tools " << args << ":\n" << std::string(out.begin(), out.end());
}

}  // namespace

#define SKIP_WITHOUT_TOOL()                                                                             \
    if (!haveTool())                                                                                    \
    SG_SKIP_OR_FAIL("3d-tiles-tools not installed ("                                                    \
                    << kTool                                                                            \
                    << "): `cmake --build build/release --target tiles-tools` fetches it from the npm " \
                       "registry")

TEST(TileFormatsTools, ParsesTilesTheToolMakesFromASavedGlb) {
    SKIP_WITHOUT_TOOL();
    const std::string glb = tempPath("tool_in.glb");
    writeFile(glb, triangleGlb());
    ASSERT_NO_FATAL_FAILURE(tool("glbToB3dm -i " + glb + " -o " + tempPath("tool.b3dm")));
    const Data b3 = readFile(tempPath("tool.b3dm"));
    ASSERT_EQ(sniffContent(b3.data(), b3.size()), ContentKind::B3dm);
    const B3dm b = parseB3dm("tool.b3dm", b3.data(), b3.size());
    EXPECT_EQ(Data(b.glb.data, b.glb.data + b.glb.size), triangleGlb());
    EXPECT_EQ(b.batchLength, 0u);
    EXPECT_FALSE(b.hasRtcCenter);

    ASSERT_NO_FATAL_FAILURE(tool("glbToI3dm -i " + glb + " -o " + tempPath("tool.i3dm")));
    const Data i3 = readFile(tempPath("tool.i3dm"));
    const I3dm i = parseI3dm("tool.i3dm", i3.data(), i3.size());
    EXPECT_EQ(Data(i.glb.data, i.glb.data + i.glb.size), triangleGlb());
    ASSERT_EQ(i.instances.size(), 1u);  // one instance at the origin
    EXPECT_EQ(i.instances[0], dmat4(1.0));
}

TEST(TileFormatsTools, ToolExtractsTheGlbOfTilesWrittenHere) {
    SKIP_WITHOUT_TOOL();
    Tile t;
    t.featureJson = R"({"BATCH_LENGTH":1,"RTC_CENTER":[1,2,3]})";
    t.batchJson = R"({"name":["one"]})";
    t.body = triangleGlb();
    const Data b3 = t.bytes();
    writeFile(tempPath("mine.b3dm"), b3);
    ASSERT_NO_FATAL_FAILURE(tool("b3dmToGlb -i " + tempPath("mine.b3dm") + " -o " + tempPath("mine_b3dm.glb")));
    EXPECT_EQ(readFile(tempPath("mine_b3dm.glb")), triangleGlb());

    const Data i3 = i3dm(R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0}})", Bin().vec(1, 2, 3).d).bytes();
    writeFile(tempPath("mine.i3dm"), i3);
    ASSERT_NO_FATAL_FAILURE(tool("i3dmToGlb -i " + tempPath("mine.i3dm") + " -o " + tempPath("mine_i3dm.glb")));
    EXPECT_EQ(readFile(tempPath("mine_i3dm.glb")), triangleGlb());

    // A composite holding a composite: the tool finds the same three glbs (in order) as parseCmpt's tiles.
    const Data c = cmpt({b3, cmpt({i3, b3})});
    ASSERT_EQ(parseCmpt("mine.cmpt", c.data(), c.size()).tiles.size(), 3u);
    writeFile(tempPath("mine.cmpt"), c);
    for (int k = 0; k < 4; ++k) std::remove(tempPath("mine_cmpt_" + std::to_string(k) + ".glb").c_str());
    ASSERT_NO_FATAL_FAILURE(tool("cmptToGlb -i " + tempPath("mine.cmpt") + " -o " + tempPath("mine_cmpt.glb")));
    for (int k = 0; k < 3; ++k)
        EXPECT_EQ(readFile(tempPath("mine_cmpt_" + std::to_string(k) + ".glb")), triangleGlb()) << k;
    EXPECT_FALSE(std::ifstream(tempPath("mine_cmpt_3.glb")).good());
}

// The formats as a tileset's contents: a cmpt holding a b3dm (RTC_CENTER) and an i3dm (two instances), the
// triangle's glTF +Y up turned to +Z up under each; every placement drawn where the tile puts it.
TEST(TileFormatsInTilesets, B3dmI3dmAndCmptContentsArePlaced) {
    Tile b;
    b.featureJson = R"({"BATCH_LENGTH":0,"RTC_CENTER":[1000,0,0]})";
    b.body = triangleGlb();
    Bin pos;
    pos.vec(0, 0, 0).vec(0, 50, 0);
    const Data all = cmpt({b.bytes(), i3dm(R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0}})", pos.d).bytes()});
    writeFile(tempPath("all.cmpt"), all);
    std::ofstream(tempPath("contents.json")) << R"({"asset": {"version": "1.0"}, "geometricError": 1, "root": {
        "boundingVolume": {"sphere": [500,0,0,1000]}, "geometricError": 0, "refine": "ADD",
        "content": {"uri": "sgkit_tiles_all.cmpt"}}})";
    Tileset ts = loadTileset(tempPath("contents.json"));
    Scene scene(ts.root());
    scene.update();
    Camera cam;
    cam.setViewport(400, 300);
    cam.setPerspective(60.0, 4.0 / 3.0, 1.0, 1e5);
    cam.setLookAt(dvec3(500, 0, 3000), dvec3(500, 0, 0), dvec3(0, 1, 0));
    DrawList list;
    CullStats stats;
    CullTraversal().cull(scene, cam, CullSettings{}, list, stats);
    // The triangle (0,0,0) (1,0,0) (0,1,0) +Y up: its (0,1,0) corner goes to +Z.
    std::vector<dvec3> corners;
    for (const DrawItem& it : list.items) corners.push_back(dvec3(dmat4(it.matrix()) * dvec4(0, 1, 0, 1)) + cam.eye());
    std::sort(corners.begin(), corners.end(), [](const dvec3& a, const dvec3& b) { return a.x + a.y < b.x + b.y; });
    ASSERT_EQ(corners.size(), 3u);
    expectVec(corners[0], dvec3(0, 0, 1), 1e-3);
    expectVec(corners[1], dvec3(0, 50, 1), 1e-3);
    expectVec(corners[2], dvec3(1000, 0, 1), 1e-3);
}
