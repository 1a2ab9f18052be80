// A pick says what it struck: a glTF file written with saveGltf (EXT_mesh_features: a per-vertex, a texture and an
// implicit feature ID set; EXT_structural_metadata: a table with a column of every kind of property) is read back,
// and a pick at the pixel of each feature gives that feature's id in every set and every property's value as the
// store that was written holds it (each value also checked by hand for one row).
#include "core/PropertyTables.h"
#include "loaders/gltf/Gltf.h"
#include "loaders/tiles/Tileset.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/PickSet.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

using namespace sg;
using sg::test::le;
using sg::test::textBytes;

namespace {

constexpr int kQuads = 4, kW = 160, kH = 120;

// Column `p` of the table over bytes added to the store.
void column(PropertyStore& s, PropertyTable& t, const ClassProperty& p, const sg::test::ColumnBytes& c) {
    s.schema.classes[0].properties.push_back(p);
    PropertyColumn col;
    col.property = int(s.schema.classes[0].properties.size() - 1);
    auto span = [&](const std::vector<uint8_t>& bytes) {
        return bytes.empty() ? ByteSpan{} : ByteSpan{s.addBuffer(bytes), 0, bytes.size()};
    };
    col.values = span(c.values);
    col.arrayOffsets = span(c.arrayOffsets);
    col.stringOffsets = span(c.stringOffsets);
    t.columns.push_back(col);
}

ClassProperty prop(const std::string& id, PropertyType type, ComponentType ct = ComponentType::None) {
    return sg::test::prop(id, type, ct);
}

// Four rows: every type the metadata spec defines, a transform, a variable-length array and a noData.
ref_ptr<PropertyStore> everyKind() {
    auto s = make<PropertyStore>();
    EnumDef e;
    e.id = "use";
    e.values = {{"residential", 0}, {"office", 1}, {"retail", 2}};
    s->schema.enums.push_back(e);
    ClassDef cls;
    cls.id = "building";
    s->schema.classes.push_back(cls);
    PropertyTable t;
    t.name = "buildings";
    t.classIndex = 0;
    t.count = kQuads;
    column(*s, t, prop("height", PropertyType::Scalar, ComponentType::Float64),
           {le<double>({10.5, 20.25, 30, 45.125})});
    column(*s, t, prop("floors", PropertyType::Scalar, ComponentType::UInt16), {le<uint16_t>({3, 6, 9, 14})});
    column(*s, t, prop("name", PropertyType::String), {textBytes("ahallz\xc3\xbc"), {}, le<uint32_t>({0, 1, 5, 5, 8})});
    column(*s, t, prop("tall", PropertyType::Boolean), {{0x0a}});
    ClassProperty use = prop("use", PropertyType::Enum, ComponentType::UInt16);
    use.enumIndex = 0;
    column(*s, t, use, {le<uint16_t>({0, 1, 2, 1})});
    column(*s, t, prop("door", PropertyType::Vec3, ComponentType::Float32),
           {le<float>({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12})});
    column(*s, t, prop("frame", PropertyType::Mat2, ComponentType::Float32),
           {le<float>({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16})});
    ClassProperty level = prop("level", PropertyType::Scalar, ComponentType::Int8);
    level.normalized = true;
    level.offset = PropertyValue::ofNumber(100.0);
    level.scale = PropertyValue::ofNumber(2.0);
    column(*s, t, level, {le<int8_t>({-128, 0, 64, 127})});
    ClassProperty codes = prop("codes", PropertyType::Scalar, ComponentType::UInt8);
    codes.array = true;
    column(*s, t, codes, {le<uint8_t>({1, 2, 3, 4, 5, 6}), le<uint32_t>({0, 1, 3, 3, 6})});
    ClassProperty pair = prop("pair", PropertyType::Scalar, ComponentType::Int32);
    pair.array = true;
    pair.count = 2;
    column(*s, t, pair, {le<int32_t>({1, 2, 3, 4, 5, 6, 7, 8})});
    ClassProperty words = prop("words", PropertyType::String);
    words.array = true;
    column(*s, t, words, {textBytes("xyyzw"), le<uint32_t>({0, 1, 1, 3, 4}), le<uint32_t>({0, 1, 3, 4, 5})});
    ClassProperty age = prop("age", PropertyType::Scalar, ComponentType::Int32);
    age.noData = PropertyValue::ofInt(-1);
    age.defaultValue = PropertyValue::ofInt(99);
    column(*s, t, age, {le<int32_t>({5, -1, 7, -1})});
    s->addTable(t);
    return s;
}

// Quads side by side along x (quad i over [i - 2, i - 1.1]), quad i feature i by vertex and feature 3 - i by the
// texel its UVs name in a 2 x 2 texture, and the vertex indices as an implicit set without a table.
ref_ptr<Mesh> quads(const ref_ptr<PropertyStore>& store) {
    std::vector<vec3> p, n;
    std::vector<vec2> uv;
    std::vector<uint32_t> idx, ids;
    for (uint32_t i = 0; i < kQuads; ++i) {
        const float x0 = float(i) - 2.0f, x1 = x0 + 0.9f;
        p.insert(p.end(), {{x0, -0.45f, 0}, {x1, -0.45f, 0}, {x1, 0.45f, 0}, {x0, 0.45f, 0}});
        n.insert(n.end(), 4, vec3(0, 0, 1));
        uv.insert(uv.end(), 4, vec2((float(i % 2) + 0.5f) / 2.0f, (float(i / 2) + 0.5f) / 2.0f));
        idx.insert(idx.end(), {4 * i, 4 * i + 1, 4 * i + 2, 4 * i, 4 * i + 2, 4 * i + 3});
        ids.insert(ids.end(), 4, i);
    }
    auto m = make<Mesh>();
    m->set(p, n, idx, uv);
    std::vector<uint8_t> rgba(16, 255);
    for (int t = 0; t < 4; ++t) rgba[size_t(t) * 4] = uint8_t(3 - t);  // texel t (row-major, top row first): 3 - t
    auto f = make<MeshFeatures>();
    FeatureIdSet byVertex;
    byVertex.label = "by vertex";
    byVertex.featureCount = kQuads;
    byVertex.propertyTable = 0;
    byVertex.ids = ids;
    FeatureIdSet byTexel;
    byTexel.source = FeatureIdSet::Source::Texture;
    byTexel.featureCount = kQuads;
    byTexel.propertyTable = 0;
    byTexel.texture = make<Texture>(2, 2, rgba);
    byTexel.channels = {0};
    FeatureIdSet implicit;
    implicit.source = FeatureIdSet::Source::Implicit;
    implicit.featureCount = 4 * kQuads;
    f->sets = {byVertex, byTexel, implicit};
    f->store = store;
    m->setFeatures(f);
    return m;
}

const PropertyValue* find(const PropertyList& l, const std::string& id) {
    for (const auto& [k, v] : l)
        if (k == id) return &v;
    return nullptr;
}

}  // namespace

TEST(FeaturePick, EachPropertyOfEachFeatureSetIsReadAtItsPixelFromTheFileWritten) {
    const ref_ptr<PropertyStore> store = everyKind();
    auto root = make<Group>();
    root->addChild(make<Geometry>(quads(store), make<Material>()));
    const std::string path = ::testing::TempDir() + "sgkit_featurepick.glb";
    saveGltf(*root, path);
    const GltfScene loaded = loadGltf(path);

    Scene scene(loaded.root);
    scene.update();
    Camera cam;
    cam.setViewport(kW, kH);
    cam.setPerspective(45.0, double(kW) / kH, 0.1, 100.0);
    cam.setLookAt(dvec3(-0.05, 0, 5), dvec3(-0.05, 0, 0), dvec3(0, 1, 0));  // glTF's +Y up, as saved
    IntersectTraversal traversal;
    const Schema& schema = store->schema;
    for (int i = 0; i < kQuads; ++i) {
        // The pixel of quad i's centre.
        const dvec4 clip = cam.projection() * cam.view() * dvec4(double(i) - 1.55, 0.0, 0.0, 1.0);
        const double x = (clip.x / clip.w * 0.5 + 0.5) * kW, y = (0.5 - clip.y / clip.w * 0.5) * kH;
        const PickSet::Result r = PickSet().pick(traversal, scene, cam, x, y);
        ASSERT_TRUE(r.hit) << "quad " << i;
        const HitFeatures hf = featuresAt(r.nearest);
        ASSERT_EQ(hf.features.size(), 3u);
        EXPECT_EQ(hf.features[0].label, "by vertex");
        EXPECT_EQ(hf.features[0].featureId, i);
        EXPECT_EQ(hf.features[1].featureId, 3 - i);      // the texel's
        EXPECT_EQ(hf.features[2].featureId / 4, i);      // one of quad i's vertices
        EXPECT_TRUE(hf.features[2].properties.empty());  // no table
        for (int s = 0; s < 2; ++s) {
            const FeatureAtHit& f = hf.features[size_t(s)];
            EXPECT_EQ(f.classId, "building");
            ASSERT_EQ(f.properties.size(), schema.classes[0].properties.size());
            // By id: saveGltf writes a schema's properties in their ids' order, not in the store's.
            for (size_t p = 0; p < f.properties.size(); ++p) {
                const std::string& id = schema.classes[0].properties[p].id;
                ASSERT_NE(find(f.properties, id), nullptr) << id;
                EXPECT_EQ(find(f.properties, id)->toJson(), store->value(0, uint64_t(f.featureId), int(p)).toJson())
                    << "quad " << i << " set " << s << " property " << id;
            }
        }
        if (i != 1) continue;
        // Row 1 by hand: what each kind reads as.
        const PropertyList& row = hf.features[0].properties;
        EXPECT_EQ(find(row, "height")->number, 20.25);
        EXPECT_EQ(find(row, "floors")->unsignedInteger, 6u);
        EXPECT_EQ(find(row, "name")->string, "hall");
        EXPECT_TRUE(find(row, "tall")->boolean);
        EXPECT_EQ(find(row, "use")->string, "office");
        EXPECT_EQ(find(row, "door")->toJson(), "[4,5,6]");
        EXPECT_EQ(find(row, "frame")->toJson(), "[5,6,7,8]");
        EXPECT_EQ(find(row, "level")->number, 100.0);  // 0 normalized, then 100 + 2 x 0
        EXPECT_EQ(find(row, "codes")->toJson(), "[2,3]");
        EXPECT_EQ(find(row, "pair")->toJson(), "[3,4]");
        EXPECT_EQ(find(row, "words")->toJson(), "[]");
        EXPECT_EQ(find(row, "age")->integer, 99);  // noData: the default
    }
}

namespace {

void put32(std::string& s, size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) s[at + size_t(i)] = char((v >> (8 * i)) & 0xff);
}

// A glb of two triangles in glTF's XZ plane (+Y up, so +Z up in a tile), side by side along x, whose _BATCHID
// attribute names batch 0 for x in [0, 1] and 1 for x in [2, 3].
std::string batchedGlb() {
    const float pos[18] = {0, 0, 0, 1, 0, 0, 0, 0, -1, 2, 0, 0, 3, 0, 0, 2, 0, -1};
    const float ids[6] = {0, 0, 0, 1, 1, 1};
    std::string bin(sizeof pos + sizeof ids, '\0');
    std::memcpy(&bin[0], pos, sizeof pos);
    std::memcpy(&bin[sizeof pos], ids, sizeof ids);
    const std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0,"_BATCHID":1}}]}],
"accessors":[{"bufferView":0,"componentType":5126,"count":6,"type":"VEC3","min":[0,0,-1],"max":[3,0,0]},
{"bufferView":1,"componentType":5126,"count":6,"type":"SCALAR"}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":72},{"buffer":0,"byteOffset":72,"byteLength":24}],
"buffers":[{"byteLength":96}]})";
    std::string j = json;
    while (j.size() % 4) j += ' ';
    std::string glb = "glTF" + std::string(8, '\0') + std::string(8, '\0') + j + std::string(8, '\0') + bin;
    put32(glb, 4, 2);
    put32(glb, 8, uint32_t(glb.size()));
    put32(glb, 12, uint32_t(j.size()));
    std::memcpy(&glb[16], "JSON", 4);
    put32(glb, 20 + j.size(), uint32_t(bin.size()));
    std::memcpy(&glb[24 + j.size()], "BIN\0", 4);
    return glb;
}

// A b3dm (28-byte header, sections padded to 8 bytes) holding `glb` with that batch table (JSON only).
std::string b3dm(const std::string& batchJson, const std::string& glb) {
    std::string ft = R"({"BATCH_LENGTH":2})", bt = batchJson;
    while ((28 + ft.size()) % 8) ft += ' ';
    while ((28 + ft.size() + bt.size()) % 8) bt += ' ';
    std::string d = "b3dm" + std::string(24, '\0') + ft + bt + glb;
    while (d.size() % 8) d += '\0';
    put32(d, 4, 1);
    put32(d, 8, uint32_t(d.size()));
    put32(d, 12, uint32_t(ft.size()));
    put32(d, 20, uint32_t(bt.size()));
    return d;
}

}  // namespace

TEST(FeaturePick, ABatchTablesRowIsReadAtEachBatchsPixelThroughATileset) {
    const std::string dir = ::testing::TempDir();
    std::ofstream(dir + "sgkit_batched.b3dm", std::ios::binary)
        << b3dm(R"({"height":[10.5,20],"name":["low","tall"],"tags":[[1,2],[3,4]]})", batchedGlb());
    std::ofstream(dir + "sgkit_batched.json") << R"({"asset":{"version":"1.0"},"geometricError":1,"root":{
        "boundingVolume":{"box":[1.5,0.5,0,2,0,0,0,1,0,0,0,1]},"geometricError":0,"refine":"ADD",
        "content":{"uri":"sgkit_batched.b3dm"}}})";
    Tileset ts = loadTileset(dir + "sgkit_batched.json");
    Scene scene(ts.root());
    scene.update();
    Camera cam;
    cam.setViewport(kW, kH);
    cam.setPerspective(45.0, double(kW) / kH, 0.1, 100.0);
    cam.setLookAt(dvec3(1.5, 0.5, 6), dvec3(1.5, 0.5, 0), dvec3(0, 1, 0));  // from above: the tile is +Z up
    IntersectTraversal traversal;
    const char* names[2] = {"low", "tall"};
    const double heights[2] = {10.5, 20.0};
    for (int b = 0; b < 2; ++b) {
        // Triangle b's centroid, in the tile's +Z-up frame: glTF's (x, 0, z) is (x, -z, 0).
        const dvec3 c(2.0 * b + 1.0 / 3.0, 1.0 / 3.0, 0.0);
        const dvec4 clip = cam.projection() * cam.view() * dvec4(c, 1.0);
        const double x = (clip.x / clip.w * 0.5 + 0.5) * kW, y = (0.5 - clip.y / clip.w * 0.5) * kH;
        const PickSet::Result r = PickSet().pick(traversal, scene, cam, x, y);
        ASSERT_TRUE(r.hit) << "batch " << b;
        const HitFeatures hf = featuresAt(r.nearest);
        ASSERT_EQ(hf.features.size(), 1u);
        const FeatureAtHit& f = hf.features[0];
        EXPECT_EQ(f.featureId, b);
        EXPECT_EQ(f.set, 0u);
        EXPECT_EQ(find(f.properties, "name")->string, names[b]);
        EXPECT_EQ(find(f.properties, "height")->asNumber(), heights[b]);
        EXPECT_EQ(find(f.properties, "tags")->toJson(), b == 0 ? "[1,2]" : "[3,4]");
        EXPECT_EQ(r.nearest.geometry->mesh()->source().file, dir + "sgkit_batched.b3dm");
    }
}
