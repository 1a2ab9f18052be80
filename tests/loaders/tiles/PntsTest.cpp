// Point cloud tiles (.pnts): tiles written here byte by byte per the spec (and a Draco stream made with Draco's own
// encoder) read back as a points mesh with its colours, normals and features; malformed ones refused with their place
// and reason; a tileset's pnts content loads with the tile's geometric error as its point spacing.
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"
#include "loaders/tiles/internal/Pnts.h"
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/core/Features.h"
#include "sg/scene/internal/DistinctGeometries.h"

#include <draco/compression/encode.h>
#include <draco/point_cloud/point_cloud_builder.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace sg;
using namespace sg::tiles;
using Data = std::vector<unsigned char>;

// Little-endian binary bodies.
struct Bin {
    Data d;
    Bin& u8(uint8_t v) {
        d.push_back(v);
        return *this;
    }
    Bin& u16(uint16_t v) { return u8(uint8_t(v & 0xff)).u8(uint8_t(v >> 8)); }
    Bin& u32(uint32_t v) { return u16(uint16_t(v & 0xffff)).u16(uint16_t(v >> 16)); }
    Bin& f32(float f) {
        uint32_t u;
        std::memcpy(&u, &f, 4);
        return u32(u);
    }
    Bin& vec(float x, float y, float z) { return f32(x).f32(y).f32(z); }
};

// A pnts laid out per the spec: the feature table JSON padded with spaces so that the binary starts on 8 bytes, the
// binaries padded to 8 bytes.
Data pnts(const std::string& featureJson, Data featureBin, const std::string& batchJson = "", Data batchBin = {}) {
    std::string ft = featureJson, bt = batchJson;
    while ((28 + ft.size()) % 8) ft += ' ';
    while (featureBin.size() % 8) featureBin.push_back(0);
    if (!bt.empty())
        while (bt.size() % 8) bt += ' ';
    while (batchBin.size() % 8) batchBin.push_back(0);
    const size_t total = 28 + ft.size() + featureBin.size() + bt.size() + batchBin.size();
    Bin h;
    h.u8('p').u8('n').u8('t').u8('s').u32(1).u32(uint32_t(total)).u32(uint32_t(ft.size()));
    h.u32(uint32_t(featureBin.size())).u32(uint32_t(bt.size())).u32(uint32_t(batchBin.size()));
    Data d = h.d;
    d.insert(d.end(), ft.begin(), ft.end());
    d.insert(d.end(), featureBin.begin(), featureBin.end());
    d.insert(d.end(), bt.begin(), bt.end());
    d.insert(d.end(), batchBin.begin(), batchBin.end());
    return d;
}

// The four corners of a unit square in x-z (the spec's examples).
Bin square() {
    Bin b;
    b.vec(0, 0, 0).vec(1, 0, 0).vec(0, 0, 1).vec(1, 0, 1);
    return b;
}

struct Read {
    ref_ptr<Node> node;
    std::vector<std::string> warnings;
    const Transform& transform() const { return static_cast<const Transform&>(*node); }
    const Geometry& geometry() const { return static_cast<const Geometry&>(*transform().child(0)); }
    const Mesh& mesh() const { return *geometry().mesh(); }
    const Material& material() const { return *geometry().material(); }
};

Read read(const Data& d) {
    Read r;
    r.node = readPnts("t.pnts", d.data(), d.size(), r.warnings);
    EXPECT_EQ(r.node->kind(), NodeKind::Transform);
    return r;
}

void expectError(const Data& d, const std::string& path, const std::string& reason) {
    std::vector<std::string> warnings;
    try {
        readPnts("t.pnts", d.data(), d.size(), warnings);
        ADD_FAILURE() << "no LoadError; expected " << path << ": " << reason;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath(), path) << e.what();
        EXPECT_NE(e.reason().find(reason), std::string::npos) << "reason: " << e.reason();
    }
}

void expectVec(const vec3& a, const vec3& b, float eps = 1e-6f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

TEST(Pnts, PositionsRelativeToRtcCenterAndRgb) {
    Bin b = square();
    b.u8(255).u8(0).u8(0).u8(0).u8(255).u8(0).u8(0).u8(0).u8(255).u8(255).u8(255).u8(0);
    const Read r = read(pnts(R"({"POINTS_LENGTH": 4, "RTC_CENTER": [1215013.8, -4736316.7, 4081608.4],
                                 "POSITION": {"byteOffset": 0}, "RGB": {"byteOffset": 48}})",
                             b.d));
    const dmat4 m = r.transform().matrix();
    EXPECT_EQ(dvec3(m[3]), dvec3(1215013.8, -4736316.7, 4081608.4));  // kept in double
    const Mesh& mesh = r.mesh();
    EXPECT_EQ(mesh.primitive(), Primitive::Points);
    ASSERT_EQ(mesh.pointCount(), 4u);
    expectVec(mesh.positions()[1], vec3(1, 0, 0));
    expectVec(mesh.positions()[3], vec3(1, 0, 1));
    ASSERT_EQ(mesh.colors().size(), 4u);
    EXPECT_EQ(mesh.colors()[0], vec4(1, 0, 0, 1));
    EXPECT_EQ(mesh.colors()[2], vec4(0, 0, 1, 1));
    EXPECT_EQ(mesh.colors()[3], vec4(1, 1, 0, 1));
    EXPECT_TRUE(mesh.normals().empty());
    EXPECT_FALSE(mesh.features());
    EXPECT_EQ(r.material().baseColor, vec4(1.0f));  // the colours as they are
    EXPECT_TRUE(r.material().unlit);                // no normals to light
    EXPECT_FALSE(r.material().blend);
    EXPECT_EQ(mesh.source().file, "t.pnts");
}

TEST(Pnts, QuantizedPositionsAndOctNormals) {
    Bin b;
    b.u16(0).u16(0).u16(0).u16(65535).u16(0).u16(0).u16(0).u16(0).u16(65535).u16(65535).u16(0).u16(65535);
    for (int i = 0; i < 4; ++i) b.u8(128).u8(255);
    const Read r = read(pnts(R"({"POINTS_LENGTH": 4, "RTC_CENTER": [10, 20, 30],
                                 "QUANTIZED_VOLUME_OFFSET": [-250.0, 0.0, -250.0],
                                 "QUANTIZED_VOLUME_SCALE": [500.0, 0.0, 500.0],
                                 "POSITION_QUANTIZED": {"byteOffset": 0}, "NORMAL_OCT16P": {"byteOffset": 24}})",
                             b.d));
    // The volume's offset joins RTC_CENTER in the transform; the floats span the scale.
    EXPECT_EQ(dvec3(r.transform().matrix()[3]), dvec3(-240, 20, -220));
    const Mesh& mesh = r.mesh();
    ASSERT_EQ(mesh.pointCount(), 4u);
    expectVec(mesh.positions()[0], vec3(0, 0, 0));
    expectVec(mesh.positions()[1], vec3(500, 0, 0));
    expectVec(mesh.positions()[3], vec3(500, 0, 500));
    ASSERT_EQ(mesh.normals().size(), 4u);
    // (128, 255) is +Y within the 8-bit encoding's step (the spec's example).
    expectVec(mesh.normals()[2], vec3(0, 1, 0), 0.01f);
    EXPECT_FALSE(r.material().unlit);
    EXPECT_EQ(r.material().baseColor, Material().baseColor);  // no colour: the default
}

TEST(Pnts, HigherPrecisionSemanticsWin) {
    Bin b = square();                                            // POSITION at 0
    for (int i = 0; i < 4; ++i) b.u16(0).u16(0).u16(0);          // POSITION_QUANTIZED at 48: all at the volume's corner
    for (int i = 0; i < 4; ++i) b.vec(0, 0, 1);                  // NORMAL at 72
    for (int i = 0; i < 4; ++i) b.u8(0).u8(0);                   // NORMAL_OCT16P at 120
    for (int i = 0; i < 4; ++i) b.u8(10).u8(20).u8(30).u8(128);  // RGBA at 128
    for (int i = 0; i < 4; ++i) b.u8(1).u8(2).u8(3);             // RGB at 144
    const Read r = read(pnts(R"({"POINTS_LENGTH": 4, "POSITION": {"byteOffset": 0},
        "POSITION_QUANTIZED": {"byteOffset": 48}, "QUANTIZED_VOLUME_OFFSET": [5, 5, 5],
        "QUANTIZED_VOLUME_SCALE": [1, 1, 1], "NORMAL": {"byteOffset": 72}, "NORMAL_OCT16P": {"byteOffset": 120},
        "RGBA": {"byteOffset": 128}, "RGB": {"byteOffset": 144}, "CONSTANT_RGBA": [9, 9, 9, 9]})",
                             b.d));
    EXPECT_EQ(dvec3(r.transform().matrix()[3]), dvec3(0.0));  // POSITION: no volume offset
    expectVec(r.mesh().positions()[3], vec3(1, 0, 1));
    expectVec(r.mesh().normals()[0], vec3(0, 0, 1));
    EXPECT_EQ(r.mesh().colors()[1], vec4(10 / 255.0f, 20 / 255.0f, 30 / 255.0f, 128 / 255.0f));
    EXPECT_TRUE(r.material().blend);  // alpha below 1
    EXPECT_EQ(r.material().baseColor, vec4(1.0f));
}

TEST(Pnts, Rgb565AndConstantRgba) {
    Bin b = square();
    b.u16(0xf800).u16(0x07e0).u16(0x001f).u16(0xffff);
    const Read r =
        read(pnts(R"({"POINTS_LENGTH": 4, "POSITION": {"byteOffset": 0}, "RGB565": {"byteOffset": 48}})", b.d));
    ASSERT_EQ(r.mesh().colors().size(), 4u);
    EXPECT_EQ(r.mesh().colors()[0], vec4(1, 0, 0, 1));
    EXPECT_EQ(r.mesh().colors()[1], vec4(0, 1, 0, 1));
    EXPECT_EQ(r.mesh().colors()[2], vec4(0, 0, 1, 1));
    EXPECT_EQ(r.mesh().colors()[3], vec4(1, 1, 1, 1));

    const Read c = read(
        pnts(R"({"POINTS_LENGTH": 4, "POSITION": {"byteOffset": 0}, "CONSTANT_RGBA": [255, 0, 51, 255]})", square().d));
    EXPECT_TRUE(c.mesh().colors().empty());  // one colour for all: the material's
    EXPECT_EQ(c.material().baseColor, vec4(1.0f, 0.0f, 0.2f, 1.0f));
    EXPECT_FALSE(c.material().blend);
}

// BATCH_ID of each width: an attribute set of BATCH_LENGTH features over the batch table.
TEST(Pnts, BatchIdsOfEachWidthNameBatchTableRows) {
    for (const char* type : {"UNSIGNED_BYTE", "UNSIGNED_SHORT", "UNSIGNED_INT", ""}) {
        SCOPED_TRACE(type);
        Bin b = square();
        const std::string t = type;
        for (uint32_t id : {0u, 0u, 1u, 1u}) {
            if (t == "UNSIGNED_BYTE") b.u8(uint8_t(id));
            if (t == "UNSIGNED_SHORT" || t.empty()) b.u16(uint16_t(id));  // UNSIGNED_SHORT when not given
            if (t == "UNSIGNED_INT") b.u32(id);
        }
        const std::string typeJson = t.empty() ? "" : R"(, "componentType": ")" + t + "\"";
        const Read r = read(pnts(R"({"POINTS_LENGTH": 4, "BATCH_LENGTH": 2, "POSITION": {"byteOffset": 0},
                                     "BATCH_ID": {"byteOffset": 48)" +
                                     typeJson + "}}",
                                 b.d, R"({"names": ["object1", "object2"]})"));
        const MeshFeatures* f = r.mesh().features();
        ASSERT_TRUE(f);
        ASSERT_EQ(f->sets.size(), 1u);
        EXPECT_EQ(f->sets[0].source, FeatureIdSet::Source::Attribute);
        EXPECT_EQ(f->sets[0].ids, (std::vector<uint32_t>{0, 0, 1, 1}));
        EXPECT_EQ(f->sets[0].featureCount, 2u);
        EXPECT_EQ(f->sets[0].propertyTable, 0);
        ASSERT_TRUE(f->store);
        ASSERT_EQ(f->store->tables().size(), 1u);
        EXPECT_EQ(f->store->tables()[0].count, 2u);
        const int p = f->store->schema.classes.at(0).find("names");
        ASSERT_GE(p, 0);
        EXPECT_EQ(f->store->value(0, 1, p), PropertyValue::ofString("object2"));
    }
}

// Without BATCH_ID the batch table has a row per point: an implicit set (a point's index is its feature).
TEST(Pnts, PerPointBatchTableIsAnImplicitSet) {
    Bin bt;
    bt.f32(0.5f).f32(1.5f).f32(2.5f).f32(3.5f);
    const Read r = read(pnts(R"({"POINTS_LENGTH": 4, "POSITION": {"byteOffset": 0}})", square().d,
                             R"({"names": ["p1", "p2", "p3", "p4"],
                                 "height": {"byteOffset": 0, "componentType": "FLOAT", "type": "SCALAR"}})",
                             bt.d));
    const MeshFeatures* f = r.mesh().features();
    ASSERT_TRUE(f);
    ASSERT_EQ(f->sets.size(), 1u);
    EXPECT_EQ(f->sets[0].source, FeatureIdSet::Source::Implicit);
    EXPECT_EQ(f->sets[0].featureCount, 4u);
    EXPECT_EQ(f->sets[0].propertyTable, 0);
    EXPECT_EQ(f->idAt(0, 2), 2);
    ASSERT_TRUE(f->store);
    EXPECT_EQ(f->store->tables()[0].count, 4u);
    const int h = f->store->schema.classes.at(0).find("height");
    ASSERT_GE(h, 0);
    EXPECT_EQ(f->store->value(0, 3, h).asNumber(), 3.5);
}

// A Draco point cloud (sequential encoding: the points keep their order) holding POSITION, RGB and a batch table
// property.
struct DracoCloud {
    std::string bytes;
    int position = -1, color = -1, intensity = -1;
};

DracoCloud dracoCloud(const std::vector<vec3>& positions, const std::vector<uint8_t>& rgb,
                      const std::vector<uint8_t>& intensity) {
    draco::PointCloudBuilder b;
    const uint32_t n = uint32_t(positions.size());
    b.Start(n);
    const int pos = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    const int col = b.AddAttribute(draco::GeometryAttribute::COLOR, 3, draco::DT_UINT8);
    const int gen = b.AddAttribute(draco::GeometryAttribute::GENERIC, 1, draco::DT_UINT8);
    for (uint32_t i = 0; i < n; ++i) {
        b.SetAttributeValueForPoint(pos, draco::PointIndex(i), &positions[i]);
        b.SetAttributeValueForPoint(col, draco::PointIndex(i), &rgb[3 * i]);
        b.SetAttributeValueForPoint(gen, draco::PointIndex(i), &intensity[i]);
    }
    std::unique_ptr<draco::PointCloud> cloud = b.Finalize(false);
    EXPECT_TRUE(cloud);
    draco::Encoder e;
    e.SetEncodingMethod(draco::POINT_CLOUD_SEQUENTIAL_ENCODING);
    draco::EncoderBuffer buffer;
    EXPECT_TRUE(e.EncodePointCloudToBuffer(*cloud, &buffer).ok());
    DracoCloud c;
    c.bytes.assign(buffer.data(), buffer.size());
    c.position = int(cloud->attribute(pos)->unique_id());
    c.color = int(cloud->attribute(col)->unique_id());
    c.intensity = int(cloud->attribute(gen)->unique_id());
    return c;
}

std::string dracoFeatureJson(const DracoCloud& c, uint32_t points, size_t byteLength) {
    return R"({"POINTS_LENGTH": )" + std::to_string(points) +
           R"(, "POSITION": {"byteOffset": 0}, "RGB": {"byteOffset": 0},
               "extensions": {"3DTILES_draco_point_compression": {"properties": {"POSITION": )" +
           std::to_string(c.position) + R"(, "RGB": )" + std::to_string(c.color) +
           R"(}, "byteOffset": 0, "byteLength": )" + std::to_string(byteLength) + "}}}";
}

const std::string kDracoBatchJson = R"({"intensity": {"byteOffset": 0, "componentType": "UNSIGNED_BYTE",
    "type": "SCALAR"}, "extensions": {"3DTILES_draco_point_compression": {"properties": {"intensity": ID}}}})";

TEST(Pnts, DracoCompressedPointsAndBatchTable) {
    const std::vector<vec3> positions = {vec3(0, 0, 0), vec3(1, 2, 3), vec3(-4, 5.5f, 6), vec3(7, 8, -9)};
    const std::vector<uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 51, 102, 153};
    const std::vector<uint8_t> intensity = {10, 20, 30, 40};
    const DracoCloud c = dracoCloud(positions, rgb, intensity);
    std::string batchJson = kDracoBatchJson;
    batchJson.replace(batchJson.find("ID"), 2, std::to_string(c.intensity));
    const Read r = read(pnts(dracoFeatureJson(c, 4, c.bytes.size()), Data(c.bytes.begin(), c.bytes.end()), batchJson));
    const Mesh& mesh = r.mesh();
    ASSERT_EQ(mesh.pointCount(), 4u);
    for (size_t i = 0; i < 4; ++i) expectVec(mesh.positions()[i], positions[i]);  // no quantization: exact
    ASSERT_EQ(mesh.colors().size(), 4u);
    EXPECT_EQ(mesh.colors()[1], vec4(0, 1, 0, 1));
    EXPECT_EQ(mesh.colors()[3], vec4(51 / 255.0f, 102 / 255.0f, 153 / 255.0f, 1.0f));
    const MeshFeatures* f = mesh.features();
    ASSERT_TRUE(f);
    EXPECT_EQ(f->sets.at(0).source, FeatureIdSet::Source::Implicit);
    ASSERT_TRUE(f->store);
    const int p = f->store->schema.classes.at(0).find("intensity");
    ASSERT_GE(p, 0);
    for (uint64_t i = 0; i < 4; ++i) EXPECT_EQ(f->store->value(0, i, p).asNumber(), intensity[i]) << i;
    for (const std::string& w : r.warnings) ADD_FAILURE() << w;  // the extension was read, not left out
}

TEST(Pnts, DracoStreamsThatDoNotFitAreRefused) {
    const DracoCloud c = dracoCloud({vec3(0), vec3(1), vec3(2), vec3(3)}, std::vector<uint8_t>(12, 7), {1, 2, 3, 4});
    const std::string path = "featureTable.extensions.3DTILES_draco_point_compression";
    // POINTS_LENGTH 5 against a stream of 4 points.
    expectError(pnts(dracoFeatureJson(c, 5, c.bytes.size()), Data(c.bytes.begin(), c.bytes.end())), path,
                "holds 4 points, POINTS_LENGTH is 5");
    // Bytes that are no Draco stream.
    Data garbage(c.bytes.size(), 0x5a);
    expectError(pnts(dracoFeatureJson(c, 4, garbage.size()), garbage), path, "Draco");
    // The stream past the binary.
    expectError(pnts(dracoFeatureJson(c, 4, c.bytes.size() + 64), Data(c.bytes.begin(), c.bytes.end())),
                path + ".byteLength", "past the end");
}

TEST(Pnts, MalformedTilesAreRefusedNamingThePath) {
    const std::string positions = R"("POSITION": {"byteOffset": 0})";
    const Data good = pnts(R"({"POINTS_LENGTH": 4, )" + positions + "}", square().d);
    expectError(Data(good.begin(), good.begin() + 20), "header", "shorter");
    Data truncated(good.begin(), good.end() - 8);
    expectError(truncated, "header.byteLength", "disagrees");
    // RGB's 4 x 3 bytes past the binary (48 bytes of positions, padded to 48).
    expectError(pnts(R"({"POINTS_LENGTH": 4, )" + positions + R"(, "RGB": {"byteOffset": 40}})", square().d),
                "featureTable.RGB", "past the end");
    expectError(pnts(R"({"POINTS_LENGTH": 0, )" + positions + "}", square().d), "featureTable.POINTS_LENGTH",
                "no points");
    expectError(pnts(R"({"POINTS_LENGTH": 4, "POSITION_QUANTIZED": {"byteOffset": 0}})", Data(24, 0)),
                "featureTable.QUANTIZED_VOLUME_OFFSET", "missing");
    expectError(pnts(R"({"POINTS_LENGTH": 4, "POINTS_LENGTH": )", square().d), "featureTable", "JSON");
    expectError(pnts(R"({"POINTS_LENGTH": 4})", square().d), "featureTable.POSITION", "neither");

    Bin nan = square();
    const float qnan = std::numeric_limits<float>::quiet_NaN();
    nan.d.resize(12);
    nan.vec(1, qnan, 0).vec(0, 0, 1).vec(1, 0, 1);
    expectError(pnts(R"({"POINTS_LENGTH": 4, )" + positions + "}", nan.d), "featureTable.POSITION", "point 1");
    Bin inf = square();
    inf.vec(std::numeric_limits<float>::infinity(), 0, 0);  // RTC_CENTER at 48
    expectError(pnts(R"({"POINTS_LENGTH": 4, )" + positions + R"(, "RTC_CENTER": {"byteOffset": 48}})", inf.d),
                "featureTable.RTC_CENTER", "not finite");
}

// A tileset whose root content is a pnts: drawn as points whose spacing is the tile's geometric error, counted.
TEST(Pnts, TilesetContentLoadsWithGeometricErrorAsSpacing) {
    using namespace tilestest;
    TempDir dir;
    const Data tile = pnts(R"({"POINTS_LENGTH": 4, "POSITION": {"byteOffset": 0}})", square().d);
    std::ofstream(dir / "points.pnts", std::ios::binary)
        .write(reinterpret_cast<const char*>(tile.data()), std::streamsize(tile.size()));
    for (const double error : {2.5, 0.0}) {
        SCOPED_TRACE(error);
        writeText(dir / "tileset.json", R"({"asset": {"version": "1.0"}, "geometricError": 10, "root": {
            "boundingVolume": {"sphere": [0, 0, 0, 10]}, "geometricError": )" +
                                            std::to_string(error) +
                                            R"(, "refine": "ADD", "content": {"uri": "points.pnts"}}})");
        const Tileset ts = loadTileset(dir / "tileset.json");
        std::vector<const Mesh*> meshes;
        forEachDistinctGeometry(*ts.root(), [&](const Geometry& g) { meshes.push_back(g.mesh()); });
        ASSERT_EQ(meshes.size(), 1u);
        EXPECT_EQ(meshes[0]->pointCount(), 4u);
        // Error 0 (a leaf): the cube root of the bounding sphere's volume per point, as CesiumJS takes it.
        const double expected = error > 0.0 ? error : std::cbrt(4.0 / 3.0 * M_PI * 1000.0 / 4.0);
        EXPECT_NEAR(meshes[0]->pointSpacing(), expected, 1e-4 * expected);
        EXPECT_EQ(ts.counts().points, 4u);
        for (const std::string& w : ts.warnings())
            EXPECT_EQ(w.find("pnts"), std::string::npos) << w;  // read, not skipped
    }
}

}  // namespace
