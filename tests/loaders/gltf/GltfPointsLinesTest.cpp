// glTF points and lines: every mode read (strips and loops as exact segment pairs, indexed points in index order),
// colours of each type, intensities, feature ids, quantized, meshopt and Draco points, CESIUM_primitive_outline, the
// round trip through saveGltf, and bad input refused naming its JSON path.
#include "GltfDoc.h"
#include "GltfTestUtil.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"

#include <draco/compression/encode.h>
#include <draco/point_cloud/point_cloud_builder.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

namespace {

using namespace sg;
using json = nlohmann::json;

constexpr int kFloat = 5126, kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123;
const std::string kPrim = "meshes[0].primitives[0]";
const std::string kOutlinePath = kPrim + ".extensions.CESIUM_primitive_outline.indices";

using gltftest::bytesOf;

// A document of one mesh on one node; the test adds views, accessors and primitives. Buffer 0 is embedded.
struct Doc : gltftest::GltfDoc {
    template <class T>
    int data(const std::vector<T>& v, int comp, size_t count, const char* type, bool normalized = false) {
        return accessor(view(bytesOf(v)), comp, count, type, normalized);
    }
    // A primitive of `mode` over `positions` (float), indexed by `indices` (uint16) unless empty.
    json& primitive(int mode, const std::vector<vec3>& positions, const std::vector<uint16_t>& indices = {}) {
        json p = {{"mode", mode}, {"attributes", {{"POSITION", data(positions, kFloat, positions.size(), "VEC3")}}}};
        if (!indices.empty()) p["indices"] = data(indices, kUShort, indices.size(), "SCALAR");
        j["meshes"][0]["primitives"].push_back(p);
        return j["meshes"][0]["primitives"].back();
    }
};

// The meshes of the scene's Geometries, depth first.
std::vector<const Mesh*> meshesOf(const Node& n) {
    std::vector<const Mesh*> out;
    std::function<void(const Node&)> walk = [&](const Node& x) {
        if (x.kind() == NodeKind::Geometry) out.push_back(static_cast<const Geometry&>(x).mesh());
        for (size_t i = 0; i < x.numChildren(); ++i) walk(*x.child(i));
    };
    walk(n);
    return out;
}

std::vector<uint32_t> indicesOf(const Mesh& m) {
    std::vector<uint32_t> out;
    for (size_t i = 0; i < m.indexCount(); ++i) out.push_back(m.index(i));
    return out;
}

const std::vector<vec3> kFour{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

TEST(GltfPointsLines, PointsAreThePositionsInOrderWithColoursAndNormals) {
    Doc d;
    json& p = d.primitive(0, kFour);
    p["attributes"]["COLOR_0"] =
        d.data(std::vector<vec3>{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}, kFloat, 4, "VEC3");
    p["attributes"]["NORMAL"] =
        d.data(std::vector<vec3>{{0, 0, 1}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}}, kFloat, 4, "VEC3");
    const GltfScene s = d.load();
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
    const auto ms = meshesOf(*s.root);
    ASSERT_EQ(ms.size(), 1u);
    const Mesh& m = *ms[0];
    EXPECT_EQ(m.primitive(), Primitive::Points);
    EXPECT_EQ(m.pointCount(), 4u);
    EXPECT_EQ(m.primitiveCount(), 4u);
    EXPECT_EQ(m.indexCount(), 0u);
    EXPECT_EQ(m.positions(), kFour);
    EXPECT_EQ(m.colors(), (std::vector<vec4>{{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 1}}));
    EXPECT_EQ(m.normals(), (std::vector<vec3>{{0, 0, 1}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}}));
}

TEST(GltfPointsLines, IndexedPointsAreTheIndexedVerticesInIndexOrder) {
    Doc d;
    json& p = d.primitive(0, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {2, 0, 2});
    p["attributes"]["_INTENSITY"] = d.data(std::vector<uint16_t>{10, 20, 30, 0}, kUShort, 3, "SCALAR");
    p["attributes"]["_FEATURE_ID_0"] = d.data(std::vector<float>{7, 8, 9}, kFloat, 3, "SCALAR");
    p["extensions"]["EXT_mesh_features"]["featureIds"] = {{{"featureCount", 10}, {"attribute", 0}},
                                                          {{"featureCount", 3}}};  // implicit: the vertex index
    d.uses("EXT_mesh_features", false);
    const GltfScene s = d.load();
    const Mesh& m = *meshesOf(*s.root).at(0);
    ASSERT_EQ(m.pointCount(), 3u);
    EXPECT_EQ(m.positions(), (std::vector<vec3>{{2, 0, 0}, {0, 0, 0}, {2, 0, 0}}));
    EXPECT_EQ(m.intensities(), (std::vector<uint16_t>{30, 10, 30}));
    ASSERT_NE(m.features(), nullptr);
    ASSERT_EQ(m.features()->sets.size(), 2u);
    EXPECT_EQ(m.features()->sets[0].ids, (std::vector<uint32_t>{9, 7, 9}));
    EXPECT_EQ(m.features()->idAt(1, 0), 2);  // the point stands for vertex 2 of the file
    EXPECT_EQ(m.features()->idAt(1, 1), 0);
}

TEST(GltfPointsLines, LinesStripsAndLoopsBecomeExactSegmentPairs) {
    Doc d;
    d.primitive(1, kFour, {0, 1, 2, 3});
    d.primitive(3, kFour, {0, 1, 2, 3});
    d.primitive(2, kFour, {0, 1, 2, 3});
    d.primitive(3, kFour);  // no indices: the vertices in order
    d.primitive(2, kFour);
    const GltfScene s = d.load();
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
    const auto ms = meshesOf(*s.root);
    ASSERT_EQ(ms.size(), 5u);
    for (const Mesh* m : ms) EXPECT_EQ(m->primitive(), Primitive::Lines);
    const std::vector<uint32_t> strip{0, 1, 1, 2, 2, 3}, loop{0, 1, 1, 2, 2, 3, 3, 0};
    EXPECT_EQ(indicesOf(*ms[0]), (std::vector<uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(indicesOf(*ms[1]), strip);
    EXPECT_EQ(indicesOf(*ms[2]), loop);
    EXPECT_EQ(indicesOf(*ms[3]), strip);
    EXPECT_EQ(indicesOf(*ms[4]), loop);
    EXPECT_EQ(ms[2]->lineCount(), 4u);
}

TEST(GltfPointsLines, AnOddLinesCountAndAOneVertexStripKeepTheirWholeSegmentsWithAWarning) {
    Doc d;
    d.primitive(1, kFour, {0, 1, 2});
    d.primitive(3, kFour, {1});
    const GltfScene s = d.load();
    const auto ms = meshesOf(*s.root);
    ASSERT_EQ(ms.size(), 2u);
    EXPECT_EQ(indicesOf(*ms[0]), (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(ms[1]->lineCount(), 0u);
    ASSERT_EQ(s.warnings.size(), 2u);
    EXPECT_EQ(s.warnings[0].rfind(kPrim + ".indices: ", 0), 0u) << s.warnings[0];
    EXPECT_NE(s.warnings[0].find("odd"), std::string::npos) << s.warnings[0];
    EXPECT_EQ(s.warnings[1].rfind("meshes[0].primitives[1].indices: ", 0), 0u) << s.warnings[1];
}

TEST(GltfPointsLines, ColoursOfEachTypeRead) {
    Doc d;
    const std::vector<vec3> two{{0, 0, 0}, {1, 0, 0}};
    d.primitive(0, two)["attributes"]["COLOR_0"] =
        d.data(std::vector<uint8_t>{255, 0, 51, 255, 0, 255, 0, 102}, kUByte, 2, "VEC4", true);
    d.primitive(1, two)["attributes"]["COLOR_0"] =
        d.data(std::vector<uint16_t>{65535, 0, 0, 0, 0, 65535, 0, 65535}, kUShort, 2, "VEC4", true);
    // VEC3 of bytes: each element padded to 4 bytes.
    const int v = d.view(bytesOf(std::vector<uint8_t>{0, 255, 0, 0, 255, 255, 255, 0}), 4);
    d.primitive(0, two)["attributes"]["COLOR_0"] = d.accessor(v, kUByte, 2, "VEC3", true);
    const GltfScene s = d.load();
    const auto ms = meshesOf(*s.root);
    ASSERT_EQ(ms.size(), 3u);
    ASSERT_EQ(ms[0]->colors().size(), 2u);
    EXPECT_EQ(ms[0]->colors()[0], vec4(1, 0, 51 / 255.0f, 1));
    EXPECT_EQ(ms[0]->colors()[1], vec4(0, 1, 0, 102 / 255.0f));
    EXPECT_EQ(ms[1]->colors(), (std::vector<vec4>{{1, 0, 0, 0}, {0, 1, 0, 1}}));
    EXPECT_EQ(ms[2]->colors(), (std::vector<vec4>{{0, 1, 0, 1}, {1, 1, 1, 1}}));
}

TEST(GltfPointsLines, IntensitiesOfEachTypeRead) {
    Doc d;
    const std::vector<vec3> three{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    d.primitive(0, three)["attributes"]["_INTENSITY"] =
        d.data(std::vector<uint8_t>{255, 0, 51, 0}, kUByte, 3, "SCALAR", true);  // a fraction of 65535
    d.primitive(0, three)["attributes"]["_INTENSITY"] =
        d.data(std::vector<float>{12.6f, -5.0f, 70000.0f}, kFloat, 3, "SCALAR");  // the value, clamped
    const GltfScene s = d.load();
    const auto ms = meshesOf(*s.root);
    ASSERT_EQ(ms.size(), 2u);
    EXPECT_EQ(ms[0]->intensities(), (std::vector<uint16_t>{65535, 0, 13107}));  // 51 / 255 * 65535
    EXPECT_EQ(ms[1]->intensities(), (std::vector<uint16_t>{13, 0, 65535}));

    Doc bad;
    bad.primitive(0, three)["attributes"]["_INTENSITY"] =
        bad.data(std::vector<float>{1, 2, 3, 4, 5, 6}, kFloat, 3, "VEC2");
    EXPECT_EQ(bad.refusal().first, kPrim + ".attributes._INTENSITY");
}

TEST(GltfPointsLines, QuantizedPositionsRead) {
    Doc d;
    d.uses("KHR_mesh_quantization", true);
    const std::vector<int16_t> shorts{0, 0, 0, 0, 100, -200, 300, 0};   // VEC3 padded to 8 bytes
    const std::vector<int8_t> bytes{127, -127, 0, 0, 0, 127, -128, 0};  // normalized, padded to 4
    d.j["meshes"][0]["primitives"].push_back(
        {{"mode", 0}, {"attributes", {{"POSITION", d.accessor(d.view(bytesOf(shorts), 8), kShort, 2, "VEC3")}}}});
    d.j["meshes"][0]["primitives"].push_back(
        {{"mode", 1}, {"attributes", {{"POSITION", d.accessor(d.view(bytesOf(bytes), 4), kByte, 2, "VEC3", true)}}}});
    const GltfScene s = d.load();
    const auto ms = meshesOf(*s.root);
    ASSERT_EQ(ms.size(), 2u);
    EXPECT_EQ(ms[0]->positions(), (std::vector<vec3>{{0, 0, 0}, {100, -200, 300}}));
    EXPECT_EQ(ms[1]->positions(), (std::vector<vec3>{{1, -1, 0}, {0, 1, -1}}));  // -128 reads as -1
    EXPECT_EQ(indicesOf(*ms[1]), (std::vector<uint32_t>{0, 1}));
}

TEST(GltfPointsLines, MeshoptCompressedPointsDecode) {
    const std::vector<float> vertices{0, 0, 0, 0, 1, 2, 3, 0, -4, 5, 6, 0, 7, 8, -9, 0};  // xyz + padding
    std::vector<unsigned char> b(meshopt_encodeVertexBufferBound(4, 16));
    b.resize(meshopt_encodeVertexBuffer(b.data(), b.size(), vertices.data(), 4, 16));
    Doc d;
    d.view(std::string(b.begin(), b.end()));  // view 0: the compressed bytes, which nothing reads directly
    d.j["buffers"].push_back({{"byteLength", 64}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    d.j["bufferViews"].push_back({{"buffer", 1},
                                  {"byteLength", 64},
                                  {"byteStride", 16},
                                  {"extensions",
                                   {{"EXT_meshopt_compression",
                                     {{"buffer", 0},
                                      {"byteOffset", 0},
                                      {"byteLength", b.size()},
                                      {"byteStride", 16},
                                      {"count", 4},
                                      {"mode", "ATTRIBUTES"}}}}}});
    d.j["meshes"][0]["primitives"].push_back(
        {{"mode", 0}, {"attributes", {{"POSITION", d.accessor(1, kFloat, 4, "VEC3")}}}});
    d.uses("EXT_meshopt_compression", true);
    const GltfScene s = d.load();
    const Mesh& m = *meshesOf(*s.root).at(0);
    EXPECT_EQ(m.primitive(), Primitive::Points);
    EXPECT_EQ(m.positions(), (std::vector<vec3>{{0, 0, 0}, {1, 2, 3}, {-4, 5, 6}, {7, 8, -9}}));
}

// A Draco point cloud of 10 points (x = 0..9) with 8-bit colours, as glTF names it; Draco may reorder the points.
struct DracoPoints {
    Doc d;
    DracoPoints() {
        draco::PointCloudBuilder b;
        b.Start(10);
        const int pos = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
        const int col = b.AddAttribute(draco::GeometryAttribute::COLOR, 4, draco::DT_UINT8);
        for (uint32_t i = 0; i < 10; ++i) {
            const vec3 p(float(i), 0.0f, 0.0f);
            const uint8_t c[4] = {uint8_t(i * 25), 0, 0, 255};
            b.SetAttributeValueForPoint(pos, draco::PointIndex(i), &p);
            b.SetAttributeValueForPoint(col, draco::PointIndex(i), c);
        }
        std::unique_ptr<draco::PointCloud> cloud = b.Finalize(false);
        draco::EncoderBuffer out;
        EXPECT_TRUE(draco::Encoder().EncodePointCloudToBuffer(*cloud, &out).ok());
        d.view(std::string(out.data(), out.size()));
        const int pa = d.accessor(-1, kFloat, 10, "VEC3"), ca = d.accessor(-1, kUByte, 10, "VEC4", true);
        json x = {
            {"bufferView", 0},
            {"attributes",
             {{"POSITION", cloud->attribute(pos)->unique_id()}, {"COLOR_0", cloud->attribute(col)->unique_id()}}}};
        d.j["meshes"][0]["primitives"].push_back({{"mode", 0},
                                                  {"attributes", {{"POSITION", pa}, {"COLOR_0", ca}}},
                                                  {"extensions", {{"KHR_draco_mesh_compression", x}}}});
        d.uses("KHR_draco_mesh_compression", true);
    }
};

TEST(GltfPointsLines, DracoPointsDecodeAndDracoLinesAreRefused) {
    DracoPoints dp;
    const GltfScene s = dp.d.load();
    const Mesh& m = *meshesOf(*s.root).at(0);
    EXPECT_EQ(m.primitive(), Primitive::Points);
    ASSERT_EQ(m.pointCount(), 10u);
    ASSERT_EQ(m.colors().size(), 10u);
    for (size_t i = 0; i < 10; ++i) {  // each point keeps its own colour
        const float x = std::round(m.positions()[i].x);
        EXPECT_FLOAT_EQ(m.colors()[i].r, x * 25.0f / 255.0f) << i;
    }
    const std::string ext = kPrim + ".extensions.KHR_draco_mesh_compression";
    DracoPoints lines;
    lines.d.j["meshes"][0]["primitives"][0]["mode"] = 1;
    const auto [path, why] = lines.d.refusal();
    EXPECT_EQ(path, ext);
    EXPECT_NE(why.find("lines"), std::string::npos) << why;
    DracoPoints indexed;  // a point cloud has no indices to decode
    indexed.d.j["meshes"][0]["primitives"][0]["indices"] = indexed.d.accessor(-1, kUShort, 10, "SCALAR");
    EXPECT_EQ(indexed.d.refusal().first, ext);
}

// A quad of two triangles with its four edges as the outline (the diagonal left out).
Doc outlined(const std::vector<uint16_t>& edges) {
    Doc d;
    json& p = d.primitive(4, kFour, {0, 1, 2, 0, 2, 3});
    p["extensions"]["CESIUM_primitive_outline"]["indices"] = d.data(edges, kUShort, edges.size(), "SCALAR");
    d.uses("CESIUM_primitive_outline", false);
    return d;
}

TEST(GltfPointsLines, TheOutlineIsReadAsTheMeshsEdges) {
    const GltfScene s = outlined({0, 1, 1, 2, 2, 3, 3, 0}).load();
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
    const Mesh& m = *meshesOf(*s.root).at(0);
    EXPECT_EQ(m.triangleCount(), 2u);
    EXPECT_EQ(m.outline(), (std::vector<uint32_t>{0, 1, 1, 2, 2, 3, 3, 0}));
}

TEST(GltfPointsLines, BadOutlinesAreRefusedNamingTheirAccessor) {
    auto [path, why] = outlined({0, 1, 1, 4}).refusal();
    EXPECT_EQ(path, kOutlinePath);
    EXPECT_NE(why.find("index 4 at element 3 is out of range"), std::string::npos) << why;
    std::tie(path, why) = outlined({0, 1, 1}).refusal();
    EXPECT_EQ(path, kOutlinePath);
    EXPECT_NE(why.find("odd count 3"), std::string::npos) << why;
    Doc d = outlined({0, 1});
    d.j["meshes"][0]["primitives"][0]["extensions"]["CESIUM_primitive_outline"]["indices"] = 99;
    EXPECT_EQ(d.refusal().first, kOutlinePath);
    d = outlined({0, 1});
    d.j["accessors"].back()["componentType"] = kFloat;  // 2 floats in the 4 bytes
    d.j["accessors"].back()["count"] = 1;
    EXPECT_EQ(d.refusal().first, kOutlinePath);
}

TEST(GltfPointsLines, ALineIndexPastTheVerticesIsRefused) {
    Doc d;
    d.primitive(1, kFour, {0, 1, 2, 4});
    const auto [path, why] = d.refusal();
    EXPECT_EQ(path, kPrim + ".indices");
    EXPECT_NE(why.find("index 4 at element 3 is out of range"), std::string::npos) << why;
}

TEST(GltfPointsLines, PointsLinesIntensitiesAndOutlinesRoundTripThroughSaveGltf) {
    auto points = make<Mesh>();
    points->setPoints({{0, 0, 0}, {1, 2, 3}, {-1, 0.5f, 2}}, {{1, 0, 0, 1}, {0, 1, 0, 0.5f}, {0, 0, 1, 1}});
    points->setIntensities({0, 1234, 65535});
    auto lines = make<Mesh>();
    lines->setLines({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {0, 1, 1, 2, 2, 0}, {{1, 1, 1, 1}, {0, 0, 0, 1}, {1, 0, 1, 1}});
    auto box = makeBoxMesh(dvec3(0), dvec3(1));
    box->setOutline({0, 1, 1, 2});
    auto red = make<Material>(vec4(1, 0, 0, 1));
    red->unlit = true;
    auto root = make<Group>();
    root->addChild(make<Geometry>(points, red));
    root->addChild(make<Geometry>(lines, ref_ptr<Material>()));
    root->addChild(make<Geometry>(box, ref_ptr<Material>()));
    for (const char* name : {"pl.glb", "pl.gltf"}) {
        const std::string path = ::testing::TempDir() + "sgkit_gltfpl_" + name;
        saveGltf(*root, path);
        const GltfScene s = loadGltf(path);
        const auto ms = meshesOf(*s.root);
        ASSERT_EQ(ms.size(), 3u) << name;  // the meshes without triangles are kept
        EXPECT_EQ(ms[0]->primitive(), Primitive::Points);
        EXPECT_EQ(ms[0]->positions(), points->positions());
        EXPECT_EQ(ms[0]->colors(), points->colors());
        EXPECT_EQ(ms[0]->intensities(), points->intensities());
        EXPECT_EQ(ms[1]->primitive(), Primitive::Lines);
        EXPECT_EQ(ms[1]->positions(), lines->positions());
        EXPECT_EQ(indicesOf(*ms[1]), (std::vector<uint32_t>{0, 1, 1, 2, 2, 0}));
        EXPECT_EQ(ms[1]->colors(), lines->colors());
        EXPECT_EQ(ms[2]->triangleCount(), box->triangleCount());
        EXPECT_EQ(ms[2]->outline(), (std::vector<uint32_t>{0, 1, 1, 2}));
        const auto* g = static_cast<const Geometry*>(s.root->child(0));
        ASSERT_EQ(g->kind(), NodeKind::Geometry);
        ASSERT_NE(g->material(), nullptr);
        EXPECT_EQ(g->material()->baseColor, vec4(1, 0, 0, 1));
        EXPECT_TRUE(g->material()->unlit);
        EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
    }
}

}  // namespace
