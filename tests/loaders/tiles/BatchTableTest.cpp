// 3D Tiles 1.0 batch tables into the property store: tiles written here byte by byte, every value read back
// through PropertyStore::value; the batch table hierarchy flattened; each malformation refused with its path;
// an i3dm's instances carrying their features through a tileset.
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/internal/BatchTable.h"
#include "loaders/tiles/internal/TileFormats.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Instance.h"
#include "sg/core/Features.h"
#include "sg/core/NodeVisitor.h"

#include <gtest/gtest.h>

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

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_batch_" + name; }

const std::string kHierarchy = "batchTable.extensions.3DTILES_batch_table_hierarchy";

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
        std::ifstream in(path, std::ios::binary);
        return Data(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }();
    return glb;
}

// Little-endian binary bodies.
struct Bin {
    Data d;
    Bin& u16(uint16_t v) {
        d.push_back(v & 0xff);
        d.push_back(v >> 8);
        return *this;
    }
    Bin& u32(uint32_t v) { return u16(uint16_t(v & 0xffff)).u16(uint16_t(v >> 16)); }
    Bin& f32(float f) {
        uint32_t u;
        std::memcpy(&u, &f, 4);
        return u32(u);
    }
};

void append(Data& d, const std::string& s) { d.insert(d.end(), s.begin(), s.end()); }
void append(Data& d, const Data& more) { d.insert(d.end(), more.begin(), more.end()); }

// A b3dm or i3dm (gltfFormat 1) laid out per the spec: each section padded so the next starts on 8 bytes.
Data tile(const std::string& magic, const std::string& featureJson, const Data& featureBin,
          const std::string& batchJson, const Data& batchBin) {
    const size_t header = magic == "i3dm" ? 32 : 28;
    std::string ftJson = featureJson, btJson = batchJson;
    while ((header + ftJson.size()) % 8) ftJson += ' ';
    Data ftBin = featureBin, btBin = batchBin;
    while (ftBin.size() % 8) ftBin.push_back(0);
    while ((header + ftJson.size() + ftBin.size() + btJson.size()) % 8) btJson += ' ';
    while (btBin.size() % 8) btBin.push_back(0);
    Data d;
    append(d, magic);
    Bin h;
    h.u32(1).u32(0).u32(uint32_t(ftJson.size())).u32(uint32_t(ftBin.size()));
    h.u32(uint32_t(btJson.size())).u32(uint32_t(btBin.size()));
    if (magic == "i3dm") h.u32(1);
    append(d, h.d);
    append(d, ftJson);
    append(d, ftBin);
    append(d, btJson);
    append(d, btBin);
    append(d, triangleGlb());
    while (d.size() % 8) d.push_back(0);
    const uint32_t n = uint32_t(d.size());
    for (int i = 0; i < 4; ++i) d[8 + size_t(i)] = (n >> (8 * i)) & 0xff;
    return d;
}

// The store of a b3dm of `batchLength` features with that batch table.
ref_ptr<PropertyStore> b3dmStore(uint32_t batchLength, const std::string& batchJson, const Data& batchBin = {}) {
    const Data d = tile("b3dm", "{\"BATCH_LENGTH\":" + std::to_string(batchLength) + "}", {}, batchJson, batchBin);
    const B3dm b = parseB3dm("t.b3dm", d.data(), d.size());
    std::vector<std::string> warnings;
    return readBatchTable("t.b3dm", b.batchJson, b.batchBinary, b.batchLength, warnings);
}

// Row `row`'s value of property `name` of the batch table's class.
PropertyValue value(const PropertyStore& s, uint64_t row, const std::string& name) {
    const int p = s.schema.classes.at(0).find(name);
    EXPECT_GE(p, 0) << name;
    return p < 0 ? PropertyValue() : s.value(0, row, p);
}

std::vector<double> numbers(const PropertyValue& v) {
    std::vector<double> r;
    for (const PropertyValue& i : v.items) r.push_back(i.asNumber());
    return r;
}

void expectError(const std::function<void()>& f, const std::string& path, const std::string& reason) {
    try {
        f();
        ADD_FAILURE() << "no LoadError; expected " << path << ": " << reason;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), "t.b3dm");
        EXPECT_EQ(e.jsonPath(), path) << e.what();
        EXPECT_NE(e.reason().find(reason), std::string::npos) << "reason: " << e.reason();
    }
}

}  // namespace

TEST(BatchTable, NoBatchTableNoStore) { EXPECT_FALSE(b3dmStore(2, "")); }

// Each JSON shape becomes its column type, every value read back.
TEST(BatchTable, JsonArraysBecomeColumns) {
    const auto s = b3dmStore(3, R"({"id":[10,11,12],"height":[1.5,null,3.25],"name":["a","bb","ccc"],
        "isTall":[true,false,true],"pos":[[1,2,3],[4,5,6],[7,8.5,9]],"other":[{"k":1},"x",2]})");
    ASSERT_TRUE(s);
    ASSERT_EQ(s->tables().size(), 1u);
    EXPECT_EQ(s->tables()[0].count, 3u);
    const ClassDef& c = s->schema.classes.at(0);
    EXPECT_EQ(c.id, kBatchTableClass);
    EXPECT_EQ(c.properties.at(size_t(c.find("id"))).componentType, ComponentType::Int64);
    EXPECT_EQ(c.properties.at(size_t(c.find("height"))).componentType, ComponentType::Float64);
    EXPECT_EQ(c.properties.at(size_t(c.find("name"))).type, PropertyType::String);
    EXPECT_EQ(c.properties.at(size_t(c.find("isTall"))).type, PropertyType::Boolean);
    EXPECT_EQ(c.properties.at(size_t(c.find("pos"))).type, PropertyType::Vec3);

    for (int i = 0; i < 3; ++i) EXPECT_EQ(value(*s, uint64_t(i), "id"), PropertyValue::ofInt(10 + i)) << i;
    EXPECT_EQ(value(*s, 0, "height"), PropertyValue::ofNumber(1.5));
    EXPECT_TRUE(value(*s, 1, "height").isNull());
    EXPECT_EQ(value(*s, 2, "height"), PropertyValue::ofNumber(3.25));
    EXPECT_EQ(value(*s, 0, "name"), PropertyValue::ofString("a"));
    EXPECT_EQ(value(*s, 1, "name"), PropertyValue::ofString("bb"));
    EXPECT_EQ(value(*s, 2, "name"), PropertyValue::ofString("ccc"));
    EXPECT_EQ(value(*s, 0, "isTall"), PropertyValue::ofBool(true));
    EXPECT_EQ(value(*s, 1, "isTall"), PropertyValue::ofBool(false));
    EXPECT_EQ(value(*s, 2, "isTall"), PropertyValue::ofBool(true));
    EXPECT_EQ(numbers(value(*s, 0, "pos")), (std::vector<double>{1, 2, 3}));
    EXPECT_EQ(numbers(value(*s, 1, "pos")), (std::vector<double>{4, 5, 6}));
    EXPECT_EQ(numbers(value(*s, 2, "pos")), (std::vector<double>{7, 8.5, 9}));
    // Mixed kinds: each value's JSON text.
    EXPECT_EQ(value(*s, 0, "other"), PropertyValue::ofString(R"({"k":1})"));
    EXPECT_EQ(value(*s, 1, "other"), PropertyValue::ofString(R"("x")"));
    EXPECT_EQ(value(*s, 2, "other"), PropertyValue::ofString("2"));
}

// FLOAT SCALAR at 0 (3 x 4 bytes), UNSIGNED_SHORT VEC2 at 12 (3 x 4 bytes): read in place.
TEST(BatchTable, BinaryPropertiesAreColumnsOverTheBody) {
    Bin b;
    b.f32(1.5f).f32(2.5f).f32(-3.0f).u16(1).u16(2).u16(3).u16(4).u16(5).u16(6);
    const auto s = b3dmStore(3, R"({"w":{"byteOffset":0,"componentType":"FLOAT","type":"SCALAR"},
        "uv":{"byteOffset":12,"componentType":"UNSIGNED_SHORT","type":"VEC2"}})",
                             b.d);
    ASSERT_TRUE(s);
    const ClassDef& c = s->schema.classes.at(0);
    EXPECT_EQ(c.properties.at(size_t(c.find("w"))).componentType, ComponentType::Float32);
    EXPECT_EQ(c.properties.at(size_t(c.find("uv"))).componentType, ComponentType::UInt16);
    EXPECT_EQ(c.properties.at(size_t(c.find("uv"))).type, PropertyType::Vec2);
    EXPECT_DOUBLE_EQ(value(*s, 0, "w").asNumber(), 1.5);
    EXPECT_DOUBLE_EQ(value(*s, 1, "w").asNumber(), 2.5);
    EXPECT_DOUBLE_EQ(value(*s, 2, "w").asNumber(), -3.0);
    EXPECT_EQ(numbers(value(*s, 0, "uv")), (std::vector<double>{1, 2}));
    EXPECT_EQ(numbers(value(*s, 1, "uv")), (std::vector<double>{3, 4}));
    EXPECT_EQ(numbers(value(*s, 2, "uv")), (std::vector<double>{5, 6}));
}

// Walls (features 0..2) under buildings 3 and 4 under block 5; feature 3 is a building itself. A feature reads its
// own class's values, then its ancestors'; what none of them has is Null.
TEST(BatchTable, HierarchyIsFlattenedPerFeature) {
    const auto s = b3dmStore(4, R"({"height":[1,2,3,4],"extensions":{"3DTILES_batch_table_hierarchy":{
        "classes":[{"name":"Wall","length":3,"instances":{"color":["blue","pink","green"],"windows":[2,4,6]}},
                   {"name":"Building","length":2,"instances":{"building":["b0","b1"]}},
                   {"name":"Block","length":1,"instances":{"district":["central"]}}],
        "instancesLength":6,"classIds":[0,0,0,1,1,2],"parentIds":[3,3,4,5,5,5]}}})");
    ASSERT_TRUE(s);
    EXPECT_EQ(value(*s, 0, "color"), PropertyValue::ofString("blue"));
    EXPECT_EQ(value(*s, 0, "windows"), PropertyValue::ofInt(2));
    EXPECT_EQ(value(*s, 0, "building"), PropertyValue::ofString("b0"));
    EXPECT_EQ(value(*s, 0, "district"), PropertyValue::ofString("central"));
    EXPECT_EQ(value(*s, 2, "color"), PropertyValue::ofString("green"));
    EXPECT_EQ(value(*s, 2, "windows"), PropertyValue::ofInt(6));
    EXPECT_EQ(value(*s, 2, "building"), PropertyValue::ofString("b1"));
    EXPECT_EQ(value(*s, 2, "district"), PropertyValue::ofString("central"));
    EXPECT_TRUE(value(*s, 3, "color").isNull());
    EXPECT_TRUE(value(*s, 3, "windows").isNull());
    EXPECT_EQ(value(*s, 3, "building"), PropertyValue::ofString("b0"));
    EXPECT_EQ(value(*s, 3, "district"), PropertyValue::ofString("central"));
    EXPECT_EQ(value(*s, 3, "height"), PropertyValue::ofInt(4));
}

// parentCounts, and classIds in the binary body (UNSIGNED_BYTE): instance 0 has parents 2 and 1, breadth first,
// so its "name" comes from 2 (listed first); instance 1 has none.
TEST(BatchTable, HierarchyParentCountsAndBinaryIds) {
    const auto s = b3dmStore(2, R"({"extensions":{"3DTILES_batch_table_hierarchy":{
        "classes":[{"name":"A","length":1,"instances":{"a":[7]}},
                   {"name":"B","length":2,"instances":{"name":["one","two"]}}],
        "instancesLength":3,"classIds":{"byteOffset":0,"componentType":"UNSIGNED_BYTE"},
        "parentCounts":[2,0,0],"parentIds":[2,1]}}})",
                             Data{0, 1, 1});
    ASSERT_TRUE(s);
    EXPECT_EQ(value(*s, 0, "a"), PropertyValue::ofInt(7));
    EXPECT_EQ(value(*s, 0, "name"), PropertyValue::ofString("two"));
    EXPECT_TRUE(value(*s, 1, "a").isNull());
    EXPECT_EQ(value(*s, 1, "name"), PropertyValue::ofString("one"));
}

// The spec forbids cycles; one read anyway ends, each feature keeping its own value first.
TEST(BatchTable, HierarchyCycleEnds) {
    const auto s = b3dmStore(2, R"({"extensions":{"3DTILES_batch_table_hierarchy":{
        "classes":[{"name":"A","length":1,"instances":{"a":[1]}},{"name":"B","length":1,"instances":{"b":[2]}}],
        "instancesLength":2,"classIds":[0,1],"parentIds":[1,0]}}})");
    ASSERT_TRUE(s);
    EXPECT_EQ(value(*s, 0, "a"), PropertyValue::ofInt(1));
    EXPECT_EQ(value(*s, 0, "b"), PropertyValue::ofInt(2));
    EXPECT_EQ(value(*s, 1, "a"), PropertyValue::ofInt(1));
    EXPECT_EQ(value(*s, 1, "b"), PropertyValue::ofInt(2));
}

TEST(BatchTable, MalformedIsRefusedWithItsPath) {
    const Data twelve(12, 0);  // padded to 16 bytes in the tile
    expectError([] { b3dmStore(3, R"({"height":[1,2]})"); }, "batchTable.height", "fewer than batchLength 3");
    expectError([] { b3dmStore(1, R"({"height":5})"); }, "batchTable.height", "must be an array");
    expectError([&] { b3dmStore(3, R"({"w":{"byteOffset":8,"componentType":"FLOAT","type":"SCALAR"}})", twelve); },
                "batchTable.w.byteOffset", "past the end");
    expectError([&] { b3dmStore(1, R"({"w":{"byteOffset":2,"componentType":"FLOAT","type":"SCALAR"}})", twelve); },
                "batchTable.w.byteOffset", "not a multiple");
    expectError([&] { b3dmStore(1, R"({"w":{"byteOffset":0,"componentType":"HALF","type":"SCALAR"}})", twelve); },
                "batchTable.w.componentType", "unknown");
    expectError([&] { b3dmStore(1, R"({"w":{"byteOffset":0,"componentType":"FLOAT","type":"MAT2"}})", twelve); },
                "batchTable.w.type", "SCALAR");
    const std::string classes = R"("classes":[{"name":"A","length":1,"instances":{"a":[1]}},
        {"name":"B","length":2,"instances":{"name":["x","y"]}}])";
    auto hierarchy = [&](const std::string& rest) {
        b3dmStore(2, R"({"extensions":{"3DTILES_batch_table_hierarchy":{)" + classes + "," + rest + "}}}");
    };
    expectError([&] { hierarchy(R"("instancesLength":2,"classIds":[0,2])"); }, kHierarchy + ".classIds[1]", "[0, 2)");
    expectError([&] { hierarchy(R"("instancesLength":3,"classIds":[0,1,1],"parentIds":[0,5,1])"); },
                kHierarchy + ".parentIds[1]", "[0, 3)");
    expectError([&] { hierarchy(R"("instancesLength":1,"classIds":[0])"); }, kHierarchy + ".instancesLength",
                "less than batchLength 2");
    expectError([&] { hierarchy(R"("instancesLength":2,"classIds":[0,0])"); }, kHierarchy + ".classIds",
                "more instances of class 0");
    expectError(
        [] {
            b3dmStore(1, R"({"extensions":{"3DTILES_batch_table_hierarchy":{"classes":[
                {"name":"A","length":1,"instances":{"a":[1]}},{"name":"B","length":2,"instances":{"name":["x"]}}],
                "instancesLength":1,"classIds":[0]}}})");
        },
        kHierarchy + ".classes[1].instances.name", "fewer than the class's length 2");
}

// An i3dm: BATCH_ID read per instance; its batch table has INSTANCES_LENGTH rows.
TEST(BatchTable, I3dmBatchIdsAndTable) {
    Bin ft;
    for (int k = 0; k < 6; ++k) ft.f32(float(k));
    ft.u16(1).u16(0);
    const Data d = tile("i3dm", R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},
        "BATCH_ID":{"byteOffset":24,"componentType":"UNSIGNED_SHORT"}})",
                        ft.d, R"({"name":["p","q"]})", {});
    const I3dm in = parseI3dm("t.i3dm", d.data(), d.size());
    EXPECT_EQ(in.batchIds, (std::vector<uint32_t>{1, 0}));
    std::vector<std::string> warnings;
    const auto s = readBatchTable("t.i3dm", in.batchJson, in.batchBinary, uint32_t(in.instances.size()), warnings);
    ASSERT_TRUE(s);
    EXPECT_EQ(value(*s, 0, "name"), PropertyValue::ofString("p"));
    EXPECT_EQ(value(*s, 1, "name"), PropertyValue::ofString("q"));
}

// Through a tileset: each Instance of the i3dm carries the shared features and its own index; its feature's
// properties are the batch table's row of its BATCH_ID.
TEST(BatchTable, I3dmInstancesCarryTheirFeatures) {
    Bin ft;
    for (int k = 0; k < 6; ++k) ft.f32(float(k));
    ft.u16(1).u16(0);
    const Data d = tile("i3dm", R"({"INSTANCES_LENGTH":2,"POSITION":{"byteOffset":0},
        "BATCH_ID":{"byteOffset":24,"componentType":"UNSIGNED_SHORT"}})",
                        ft.d, R"({"name":["p","q"]})", {});
    std::ofstream(tempPath("trees.i3dm"), std::ios::binary)
        .write(reinterpret_cast<const char*>(d.data()), std::streamsize(d.size()));
    std::ofstream(tempPath("trees.json")) << R"({"asset": {"version": "1.0"}, "geometricError": 1, "root": {
        "boundingVolume": {"sphere": [0,0,0,100]}, "geometricError": 0, "content": {"uri": "sgkit_batch_trees.i3dm"}}})";
    Tileset ts = loadTileset(tempPath("trees.json"));
    struct Collect : NodeVisitor {
        std::vector<Instance*> found;
        void apply(Instance& i) override { found.push_back(&i); }
    } c;
    ts.root()->accept(c);
    ASSERT_EQ(c.found.size(), 2u);
    for (uint32_t k = 0; k < 2; ++k) {
        const MeshFeatures* f = c.found[k]->features();
        ASSERT_TRUE(f);
        EXPECT_EQ(c.found[k]->featureIndex(), k);
        ASSERT_EQ(f->sets.size(), 1u);
        EXPECT_EQ(f->sets[0].source, FeatureIdSet::Source::Instance);
        EXPECT_EQ(f->sets[0].propertyTable, 0);
        ASSERT_TRUE(f->store);
        const int64_t id = f->idAt(0, k);
        EXPECT_EQ(id, k == 0 ? 1 : 0);
        EXPECT_EQ(value(*f->store, uint64_t(id), "name"), PropertyValue::ofString(k == 0 ? "q" : "p"));
    }
}
