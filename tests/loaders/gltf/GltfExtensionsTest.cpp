// What packers write: KHR_mesh_quantization, EXT_meshopt_compression with its fallback buffer, sparse accessors,
// buffers without data, cameras out of range and optional extensions the loader does not know; hand-made files
// read to the expected meshes, bad ones refused with their JSON path and reason.
#include "GltfDoc.h"
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Transform.h"

#include <gtest/gtest.h>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

using namespace sg;
using json = nlohmann::json;

namespace {

using gltftest::base64;
using gltftest::bytesOf;

// One triangle primitive, whose attributes the test writes.
struct Doc : gltftest::GltfDoc {
    Doc() : GltfDoc(R"([{"attributes": {}}])") {}
    json& primitive() { return j["meshes"][0]["primitives"][0]; }
};

constexpr int kFloat = 5126, kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125;

const Geometry* firstGeometry(const Node& n) {
    if (n.kind() == NodeKind::Geometry) return static_cast<const Geometry*>(&n);
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Geometry* g = firstGeometry(*n.child(i))) return g;
    return nullptr;
}
const Mesh* firstMesh(const Node& n) {
    const Geometry* g = firstGeometry(n);
    return g ? g->mesh() : nullptr;
}

const std::vector<vec3> kTriangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// A float triangle: POSITION and indices.
void triangle(Doc& d, const std::vector<vec3>& p = kTriangle) {
    d.primitive()["attributes"]["POSITION"] = d.accessor(d.view(bytesOf(p)), kFloat, p.size(), "VEC3");
    d.primitive()["indices"] = d.accessor(d.view(bytesOf(std::vector<uint16_t>{0, 1, 2})), kUShort, 3, "SCALAR");
}

bool mentions(const std::vector<std::string>& warnings, const std::string& a, const std::string& b) {
    for (const std::string& w : warnings)
        if (w.find(a) != std::string::npos && w.find(b) != std::string::npos) return true;
    return false;
}

// --- KHR_mesh_quantization

// Short positions (not normalized), byte normals and short tangents (normalized), unsigned short texture coordinates
// (not normalized): gltfpack's choices.
Doc quantized() {
    Doc d;
    const std::vector<int16_t> pos{0, 0, 0, 0, 100, 0, 0, 0, 0, 100, 0, 0};   // VEC3 padded to 8 bytes
    const std::vector<int8_t> nrm{0, 90, 90, 0, 0, 90, 90, 0, 0, 90, 90, 0};  // padded to 4 bytes
    const std::vector<uint16_t> uv{0, 0, 3, 0, 0, 5};
    const std::vector<int16_t> tan{32767, 0, 0, -32767, 32767, 0, 0, -32767, 30000, 10000, 0, 32767};
    json& attrs = d.primitive()["attributes"];
    attrs["POSITION"] = d.accessor(d.view(bytesOf(pos), 8), kShort, 3, "VEC3");
    attrs["NORMAL"] = d.accessor(d.view(bytesOf(nrm), 4), kByte, 3, "VEC3", true);
    attrs["TEXCOORD_0"] = d.accessor(d.view(bytesOf(uv)), kUShort, 3, "VEC2");
    attrs["TANGENT"] = d.accessor(d.view(bytesOf(tan)), kShort, 3, "VEC4", true);
    d.primitive()["indices"] = d.accessor(d.view(bytesOf(std::vector<uint8_t>{0, 1, 2, 0})), kUByte, 3, "SCALAR");
    d.uses("KHR_mesh_quantization", true);
    return d;
}

TEST(GltfQuantization, IntegerAttributesReadAsTheirValuesWithUnitNormalsAndTangents) {
    Doc d = quantized();
    const GltfScene s = d.load();
    const Mesh* m = firstMesh(*s.root);
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->positions(), (std::vector<vec3>{{0, 0, 0}, {100, 0, 0}, {0, 100, 0}}));
    EXPECT_EQ(m->uvs(), (std::vector<vec2>{{0, 0}, {3, 0}, {0, 5}}));
    ASSERT_EQ(m->normals().size(), 3u);
    ASSERT_EQ(m->tangents().size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(glm::length(m->normals()[i]), 1.0f, 1e-6f) << i;  // 90/127 * sqrt 2 is 1.002 before
        EXPECT_NEAR(glm::length(vec3(m->tangents()[i])), 1.0f, 1e-6f) << i;
    }
    EXPECT_NEAR(m->normals()[0].y, std::sqrt(0.5f), 1e-6f);
    EXPECT_FLOAT_EQ(m->tangents()[0].w, -1.0f);  // handedness kept
    EXPECT_FLOAT_EQ(m->tangents()[2].w, 1.0f);
    EXPECT_NEAR(m->tangents()[2].x, 3.0f / std::sqrt(10.0f), 1e-6f);
}

TEST(GltfQuantization, WithoutTheExtensionIntegerPositionsAreRefused) {
    Doc d = quantized();
    d.j.erase("extensionsUsed");
    d.j.erase("extensionsRequired");
    const auto [path, why] = d.refusal();
    EXPECT_EQ(path, "meshes[0].primitives[0].attributes.POSITION");
    EXPECT_NE(why.find("componentType 5122"), std::string::npos) << why;
}

TEST(GltfQuantization, NormalsOfIntegersNotNormalizedAreRefused) {
    Doc d = quantized();
    d.j["accessors"][1].erase("normalized");
    const auto [path, why] = d.refusal();
    EXPECT_EQ(path, "meshes[0].primitives[0].attributes.NORMAL");
    EXPECT_NE(why.find("must be normalized"), std::string::npos) << why;
}

TEST(GltfQuantization, UnsignedNormalsAreRefusedEvenWithTheExtension) {
    Doc d = quantized();
    d.j["accessors"][1]["componentType"] = kUByte;
    EXPECT_EQ(d.refusal().first, "meshes[0].primitives[0].attributes.NORMAL");
}

// --- EXT_meshopt_compression

// Four vertices (position + padding, 16 bytes) and two triangles, compressed into buffer 0; the views point into
// buffer 1, the fallback, which has no data.
struct Compressed {
    std::vector<float> vertices{0, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0};
    std::vector<uint32_t> triangles{0, 1, 2, 2, 3, 0};
    std::string vertexBytes, indexBytes;
    Compressed() {
        std::vector<unsigned char> b(meshopt_encodeVertexBufferBound(4, 16));
        b.resize(meshopt_encodeVertexBuffer(b.data(), b.size(), vertices.data(), 4, 16));
        vertexBytes.assign(b.begin(), b.end());
        b.assign(meshopt_encodeIndexBufferBound(6, 4), 0);
        b.resize(meshopt_encodeIndexBuffer(b.data(), b.size(), triangles.data(), 6));
        indexBytes.assign(b.begin(), b.end());
    }
};

Doc meshoptDoc(const Compressed& c, const char* ext = "EXT_meshopt_compression") {
    Doc d;
    d.j["buffers"].push_back({{"byteLength", 64 + 12}, {"extensions", {{ext, {{"fallback", true}}}}}});
    auto compressedView = [&](const std::string& bytes, size_t at, size_t length, int stride, size_t count,
                              const char* mode) {
        while (d.bin.size() % 4) d.bin.push_back('\0');
        json x = {{"buffer", 0},
                  {"byteOffset", d.bin.size()},
                  {"byteLength", bytes.size()},
                  {"byteStride", stride},
                  {"count", count},
                  {"mode", mode}};
        d.bin += bytes;
        json v = {{"buffer", 1}, {"byteOffset", at}, {"byteLength", length}, {"extensions", {{ext, x}}}};
        if (std::string(mode) == "ATTRIBUTES") v["byteStride"] = stride;
        d.j["bufferViews"].push_back(v);
        return int(d.j["bufferViews"].size()) - 1;
    };
    const int vv = compressedView(c.vertexBytes, 0, 64, 16, 4, "ATTRIBUTES");
    const int iv = compressedView(c.indexBytes, 64, 12, 2, 6, "TRIANGLES");
    d.primitive()["attributes"]["POSITION"] = d.accessor(vv, kFloat, 4, "VEC3");
    d.primitive()["indices"] = d.accessor(iv, kUShort, 6, "SCALAR");
    d.uses(ext, true);
    return d;
}

void expectDecoded(const GltfScene& s, const Compressed& c) {
    const Mesh* m = firstMesh(*s.root);
    ASSERT_NE(m, nullptr);
    ASSERT_EQ(m->positions().size(), 4u);
    for (size_t i = 0; i < 4; ++i) EXPECT_EQ(m->positions()[i], vec3(c.vertices[4 * i], c.vertices[4 * i + 1], 0.0f));
    ASSERT_EQ(m->indexCount(), 6u);
    for (size_t t = 0; t < 2; ++t) {  // the index codec may start a triangle at another corner
        size_t r = 0;
        while (r < 3 && m->index(3 * t + r) != c.triangles[3 * t]) ++r;
        for (size_t k = 0; k < 3; ++k) EXPECT_EQ(m->index(3 * t + (r + k) % 3), c.triangles[3 * t + k]) << t;
    }
}

TEST(GltfMeshopt, CompressedViewsDecodeWithoutTheFallbackBufferInGlbAndGltf) {
    const Compressed c;
    Doc d = meshoptDoc(c);
    expectDecoded(d.load(true), c);
    expectDecoded(d.load(false), c);
}

TEST(GltfMeshopt, TheKhrExtensionDecodesToo) {
    const Compressed c;
    Doc d = meshoptDoc(c, "KHR_meshopt_compression");
    expectDecoded(d.load(true), c);
}

TEST(GltfMeshopt, IndexSequencesAndOctahedralNormalsDecode) {
    Doc d;
    triangle(d);
    const std::vector<uint32_t> seq{0, 1, 2};
    std::vector<unsigned char> b(meshopt_encodeIndexSequenceBound(3, 3));
    b.resize(meshopt_encodeIndexSequence(b.data(), b.size(), seq.data(), 3));
    const std::vector<float> normals{0, 0, 1, 0, 0.6f, 0, 0.8f, 0, 0, -1, 0, 0};  // xyzw
    std::vector<int8_t> oct(12);
    meshopt_encodeFilterOct(oct.data(), 3, 4, 8, normals.data());
    std::vector<unsigned char> nb(meshopt_encodeVertexBufferBound(3, 4));
    nb.resize(meshopt_encodeVertexBuffer(nb.data(), nb.size(), oct.data(), 3, 4));
    d.j["buffers"].push_back({{"byteLength", 24}});  // no uri: meshopt's fallback without the marker
    const size_t seqAt = (d.bin.size() + 3) & ~size_t(3);
    d.view(std::string(b.begin(), b.end()));
    const size_t nAt = (d.bin.size() + 3) & ~size_t(3);
    d.view(std::string(nb.begin(), nb.end()));
    d.j["bufferViews"].push_back({{"buffer", 1},
                                  {"byteLength", 12},
                                  {"extensions",
                                   {{"EXT_meshopt_compression",
                                     {{"buffer", 0},
                                      {"byteOffset", seqAt},
                                      {"byteLength", b.size()},
                                      {"byteStride", 4},
                                      {"count", 3},
                                      {"mode", "INDICES"}}}}}});
    d.j["bufferViews"].push_back({{"buffer", 1},
                                  {"byteOffset", 12},
                                  {"byteLength", 12},
                                  {"byteStride", 4},
                                  {"extensions",
                                   {{"EXT_meshopt_compression",
                                     {{"buffer", 0},
                                      {"byteOffset", nAt},
                                      {"byteLength", nb.size()},
                                      {"byteStride", 4},
                                      {"count", 3},
                                      {"mode", "ATTRIBUTES"},
                                      {"filter", "OCTAHEDRAL"}}}}}});
    d.primitive()["indices"] = d.accessor(4, kUInt, 3, "SCALAR");
    d.primitive()["attributes"]["NORMAL"] = d.accessor(5, kByte, 3, "VEC3", true);
    d.uses("EXT_meshopt_compression", true);
    d.uses("KHR_mesh_quantization", true);
    const GltfScene s = d.load(true);
    const Mesh* m = firstMesh(*s.root);
    ASSERT_NE(m, nullptr);
    ASSERT_EQ(m->indexCount(), 3u);
    for (size_t i = 0; i < 3; ++i) EXPECT_EQ(m->index(i), i);
    ASSERT_EQ(m->normals().size(), 3u);
    for (size_t i = 0; i < 3; ++i)
        EXPECT_LT(glm::length(m->normals()[i] - vec3(normals[4 * i], normals[4 * i + 1], normals[4 * i + 2])), 0.02f)
            << i;
}

const std::string kExt = "bufferViews[0].extensions.EXT_meshopt_compression";

TEST(GltfMeshopt, DataThatDoesNotDecodeIsRefusedNamingTheView) {
    const Compressed c;
    Doc d = meshoptDoc(c);
    d.j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = c.vertexBytes.size() / 2;
    auto [path, why] = d.refusal(true);
    EXPECT_EQ(path, kExt);
    EXPECT_NE(why.find("does not decode"), std::string::npos) << why;

    d = meshoptDoc(c);
    d.bin[0] = char(0xa7);  // an unknown codec version
    std::tie(path, why) = d.refusal(true);
    EXPECT_EQ(path, kExt);
    EXPECT_NE(why.find("codec version 7 is not one meshoptimizer 0."), std::string::npos) << why;

    // Every byte flipped in turn, then cut short: refused or decoded, never a crash.
    const Compressed c2;
    for (size_t k = 0; k < c2.vertexBytes.size() + c2.indexBytes.size(); ++k) {
        Doc e = meshoptDoc(c2);
        e.bin[k] = char(~e.bin[k]);
        const std::string g = e.glb();
        try {
            loadGltfFromMemory("flipped.glb", g.data(), g.size());
        } catch (const LoadError&) {
        }
    }
}

TEST(GltfMeshopt, StridesModesFiltersAndCountsAreCheckedBeforeDecoding) {
    const Compressed c;
    struct Case {
        const char* key;
        json value;
        std::string path;
    };
    const std::vector<Case> cases{
        {"byteStride", 6, kExt + ".byteStride"},
        {"byteStride", 260, kExt + ".byteStride"},
        {"mode", "POINTS", kExt + ".mode"},
        {"filter", "QUATERNION", kExt + ".filter"},  // needs byteStride 8
        {"filter", "COLOR", kExt + ".filter"},
        {"count", 5, kExt + ".count"},           // 5 * 16 bytes: more than the view's 64
        {"count", 2147483647, kExt + ".count"},  // the limit, before any allocation
        {"count", 1e12, kExt + ".count"},
        {"buffer", 7, kExt + ".buffer"},
        {"byteOffset", 1 << 20, kExt},
        {"count", -1, kExt + ".count"},
    };
    for (const Case& k : cases) {
        Doc d = meshoptDoc(c);
        d.j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"][k.key] = k.value;
        EXPECT_EQ(d.refusal(true).first, k.path) << k.key << " " << k.value;
    }
    Doc d = meshoptDoc(c);
    d.j["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["count"] = 4;  // TRIANGLES: a multiple of 3
    EXPECT_EQ(d.refusal(true).first, "bufferViews[1].extensions.EXT_meshopt_compression.count");
}

// glTF allows a buffer without data: the primitive that reads it is skipped, naming it and the accessor.
TEST(GltfMeshopt, APrimitiveReadingTheFallbackWithoutCompressionIsSkipped) {
    const Compressed c;
    Doc d = meshoptDoc(c);
    d.j["bufferViews"][0]["extensions"].clear();
    const GltfScene s = d.load(true);
    EXPECT_EQ(firstGeometry(*s.root), nullptr);
    EXPECT_TRUE(mentions(s.warnings, "meshes[0].primitives[0]: accessors[", "has no data")) << s.warnings.size();
}

// --- Sparse accessors

Doc sparseDoc(bool withBase) {
    Doc d;
    triangle(d);
    const std::vector<uint16_t> idx{0, 2};
    const std::vector<vec3> values{{5, 5, 5}, {0, 7, 0}};
    const int iv = d.view(bytesOf(idx)), vv = d.view(bytesOf(values));
    json& a = d.j["accessors"][0];
    if (!withBase) a.erase("bufferView");
    a["sparse"] = {
        {"count", 2}, {"indices", {{"bufferView", iv}, {"componentType", kUShort}}}, {"values", {{"bufferView", vv}}}};
    return d;
}

TEST(GltfSparse, ValuesReplaceTheBaseOrZeros) {
    const GltfScene a = sparseDoc(true).load(), b = sparseDoc(false).load(true);
    EXPECT_EQ(firstMesh(*a.root)->positions(), (std::vector<vec3>{{5, 5, 5}, {1, 0, 0}, {0, 7, 0}}));
    EXPECT_EQ(firstMesh(*b.root)->positions(), (std::vector<vec3>{{5, 5, 5}, {0, 0, 0}, {0, 7, 0}}));
}

TEST(GltfSparse, BadSubstitutionsAreRefusedNamingTheirPart) {
    const std::string p = "accessors[0].sparse";
    auto refused = [](const std::function<void(json&)>& change) {
        Doc d = sparseDoc(true);
        change(d.j);
        return d.refusal();
    };
    auto r = refused([](json& j) { j["accessors"][0]["sparse"]["count"] = 4; });
    EXPECT_EQ(r.first, p + ".count");
    r = refused([](json& j) { j["accessors"][0]["sparse"]["indices"]["bufferView"] = 9; });
    EXPECT_EQ(r.first, p + ".indices.bufferView");
    r = refused([](json& j) { j["accessors"][0]["sparse"]["indices"]["componentType"] = kShort; });
    EXPECT_EQ(r.first, p + ".indices.componentType");
    r = refused([](json& j) { j["accessors"][0]["sparse"]["values"]["byteOffset"] = 4; });
    EXPECT_EQ(r.first, p + ".values");
    EXPECT_NE(r.second.find("past the end of bufferViews[3]"), std::string::npos) << r.second;
    r = refused([](json& j) { j["accessors"][0]["sparse"]["indices"]["byteOffset"] = -4; });
    EXPECT_EQ(r.first, p + ".indices.byteOffset");
}

TEST(GltfSparse, IndicesOutOfOrderOrRangeAreRefused) {
    for (const auto& [idx, what] : std::vector<std::pair<std::vector<uint16_t>, std::string>>{
             {{2, 0}, "increase strictly"}, {{1, 1}, "increase strictly"}, {{0, 3}, "out of range"}}) {
        Doc d;
        triangle(d);
        const std::vector<vec3> values{{5, 5, 5}, {0, 7, 0}};
        const int iv = d.view(bytesOf(idx)), vv = d.view(bytesOf(values));
        d.j["accessors"][0]["sparse"] = {{"count", 2},
                                         {"indices", {{"bufferView", iv}, {"componentType", kUShort}}},
                                         {"values", {{"bufferView", vv}}}};
        const auto [path, why] = d.refusal();
        EXPECT_EQ(path, "accessors[0].sparse.indices");
        EXPECT_NE(why.find(what), std::string::npos) << why;
    }
}

TEST(GltfSparse, AHugeAccessorOfZerosIsRefusedBeforeItsCopy) {
    Doc d = sparseDoc(false);
    d.j["accessors"][0]["count"] = 1 << 24;  // 192 MiB each, within the limit for accessors of zeros
    for (int k = 0; k < 3; ++k) {            // three of them: more than the dense copies may hold in all
        d.j["accessors"].push_back(d.j["accessors"][0]);
        d.j["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", k + 2}}}});
    }
    const auto [path, why] = d.refusal();
    EXPECT_EQ(path, "accessors[3].count");
}

// --- What gltfpack makes of sgkit's own files

// A Geometry node of sgkit's whose mesh a packer moved to a child node (with the dequantizing transform).
TEST(GltfQuantization, AnSgkitGeometryWhoseMeshMovedToAChildIsReadWithIt) {
    Doc d;
    triangle(d);
    d.j["nodes"] = json::parse(R"([{"extras": {"sgkit": {"kind": "Geometry"}}, "children": [1]},
                                   {"mesh": 0, "scale": [2, 2, 2], "translation": [0, 0, 5]}])");
    const GltfScene s = d.load();
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    const Mesh* m = firstMesh(*s.root);
    ASSERT_NE(m, nullptr);
    const Node* t = s.root->child(0)->child(0);
    ASSERT_EQ(t->kind(), NodeKind::Transform);
    EXPECT_EQ(static_cast<const Transform*>(t)->matrix()[3], dvec4(0, 0, 5, 1));
}

// gltfpack dequantizes texture coordinates with KHR_texture_transform; sgkit's classic materials, which the
// renderer draws without a UV transform, have it applied to their meshes' UVs instead.
TEST(GltfQuantization, AClassicMaterialsTextureTransformIsAppliedToTheUvs) {
    Doc d;
    triangle(d);
    const std::vector<vec2> uv{{0, 0}, {1, 0}, {0, 1}};
    d.primitive()["attributes"]["TEXCOORD_0"] = d.accessor(d.view(bytesOf(uv)), kFloat, 3, "VEC2");
    d.primitive()["material"] = 0;
    d.j["images"] = {{{"uri",
                       "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4nGP4z8DwHwAFAA"
                       "H/iZk9HQAAAABJRU5ErkJggg=="}}};
    d.j["textures"] = {{{"source", 0}}};
    d.j["materials"] = json::parse(R"([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions":
        {"KHR_texture_transform": {"offset": [0.5, 0.25], "scale": [2, 4]}}}},
        "extras": {"sgkit": {"shading": "classic"}}}])");
    d.uses("KHR_texture_transform", false);
    GltfScene s = d.load();
    ASSERT_NE(firstGeometry(*s.root), nullptr);
    const Geometry& geo = *firstGeometry(*s.root);
    EXPECT_EQ(geo.mesh()->uvs(), (std::vector<vec2>{{0.5f, 0.25f}, {2.5f, 0.25f}, {0.5f, 4.25f}}));
    EXPECT_EQ(geo.material()->textureTransform, mat3(1.0f));
    EXPECT_FALSE(geo.material()->physical);
    d.j["materials"][0].erase("extras");  // a physical material keeps the transform
    s = d.load();
    const Geometry& phys = *firstGeometry(*s.root);
    EXPECT_EQ(phys.mesh()->uvs(), uv);
    EXPECT_NE(phys.material()->textureTransform, mat3(1.0f));
}

// --- Buffers, cameras, extensions

TEST(GltfBuffers, AGltfBufferWithoutUriThatNothingUsesLoads) {
    Doc d;
    triangle(d);
    d.j["buffers"].push_back({{"byteLength", 1000}});
    EXPECT_EQ(firstMesh(*d.load().root)->positions(), kTriangle);
    EXPECT_EQ(firstMesh(*d.load(true).root)->positions(), kTriangle);  // and a GLB's buffer 1 is not its BIN chunk
}

// glTF allows a buffer without data (no uri outside a GLB): the nodes load, the primitive that reads it does not.
TEST(GltfBuffers, APrimitiveReadingABufferWithoutUriIsSkipped) {
    Doc d;
    triangle(d);
    d.j["buffers"].push_back({{"byteLength", 36}});
    d.j["bufferViews"][0]["buffer"] = 1;  // the positions
    const GltfScene s = d.load();
    ASSERT_TRUE(s.root);
    EXPECT_EQ(s.root->numChildren(), 1u);  // the node
    EXPECT_EQ(firstGeometry(*s.root), nullptr);
    EXPECT_TRUE(mentions(s.warnings, "meshes[0].primitives[0]: accessors[0] (attributes.POSITION)", "has no data"));
}

TEST(GltfBuffers, DataUrisInAGlbLoad) {
    Doc d;
    triangle(d);
    const std::vector<vec3> other{{0, 0, 2}, {3, 0, 2}, {0, 3, 2}};
    d.j["buffers"].push_back(
        {{"byteLength", 36}, {"uri", "data:application/octet-stream;base64," + base64(bytesOf(other))}});
    d.j["bufferViews"].push_back({{"buffer", 1}, {"byteLength", 36}});
    d.j["accessors"][0]["bufferView"] = 2;
    EXPECT_EQ(firstMesh(*d.load(true).root)->positions(), other);
}

TEST(GltfCameras, AFieldOfViewOutOfRangeIsClampedWithAWarning) {
    for (double yfov : {0.0, -1.0, 3.2, 60.0}) {
        Doc d;
        triangle(d);
        d.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", yfov}, {"znear", 0.1}}}}};
        d.j["nodes"][0]["camera"] = 0;
        const GltfScene s = d.load();
        ASSERT_EQ(s.cameras.size(), 1u);
        EXPECT_GT(s.cameras[0].yfovDegrees, 0.0) << yfov;
        EXPECT_LT(s.cameras[0].yfovDegrees, 180.0) << yfov;
        EXPECT_TRUE(mentions(s.warnings, "cameras[0].perspective.yfov", "not in (0, pi)")) << yfov;
    }
    Doc d;
    triangle(d);
    d.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
    d.j["nodes"][0]["camera"] = 0;
    const GltfScene s = d.load();
    EXPECT_NEAR(s.cameras[0].yfovDegrees, 0.8 * 180.0 / M_PI, 1e-9);
    EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfExtensions, AnUnsupportedOptionalExtensionIsAWarningARequiredOneARefusal) {
    Doc d;
    triangle(d);
    d.uses("KHR_texture_transform", false);
    d.uses("EXT_made_up", false);
    const GltfScene s = d.load();
    EXPECT_TRUE(mentions(s.warnings, "extensionsUsed[1]", "'EXT_made_up' is not supported"));
    EXPECT_FALSE(mentions(s.warnings, "KHR_texture_transform", ""));
    d.j["extensionsRequired"] = {"EXT_made_up"};
    const auto [path, why] = d.refusal();
    EXPECT_EQ(path, "extensionsRequired[0]");
    EXPECT_NE(why.find("EXT_made_up"), std::string::npos);
}

}  // namespace

// The fuzz seeds of these features load as meant (a seed that is refused explores nothing past the refusal).
TEST(GltfExtensions, TheFuzzSeedsLoad) {
    const std::string corpus = std::string(SGKIT_SOURCE_DIR) + "/fuzz/corpus/";
    const GltfScene q = loadGltf(corpus + "quantized.gltf");
    EXPECT_TRUE(mentions(q.warnings, "cameras[0].perspective.yfov", "not in (0, pi)"));
    EXPECT_TRUE(mentions(q.warnings, "extensionsUsed[1]", "EXT_made_up"));
    ASSERT_NE(firstMesh(*q.root), nullptr);
    EXPECT_EQ(firstMesh(*q.root)->tangents().size(), 3u);
    const GltfScene s = loadGltf(corpus + "sparse.gltf");
    EXPECT_EQ(firstMesh(*s.root)->positions(), (std::vector<vec3>{{5, 5, 5}, {1, 0, 0}, {0, 7, 0}}));
    const GltfScene p = loadGltf(corpus + "gltfpack-meshopt.glb");
    ASSERT_NE(firstMesh(*p.root), nullptr);
    EXPECT_GT(firstMesh(*p.root)->triangleCount(), 0u);
}
