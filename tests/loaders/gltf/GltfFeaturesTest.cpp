// glTF's EXT_mesh_features, EXT_structural_metadata and EXT_instance_features read into MeshFeatures and the
// property store, written back by saveGltf, a 3D Tiles 1.0 tile's batch ids over a given store, and bad input.
#include "GltfTestUtil.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Instance.h"
#include "nodes/Transform.h"
#include "sg/core/PropertyTableBuilder.h"
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace sg;
using nlohmann::json;

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_gltffeat_" + name; }

// A buffer the test fills, one view per array (each at a multiple of 8 bytes, as property tables want).
struct Bin {
    std::string bytes;
    json views = json::array();
    int raw(const void* p, size_t n) {
        bytes.resize((bytes.size() + 7) & ~size_t(7), '\0');
        views.push_back({{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", n}});
        bytes.append(static_cast<const char*>(p), n);
        return int(views.size() - 1);
    }
    template <class T>
    int add(const std::vector<T>& v) {
        return raw(v.data(), v.size() * sizeof(T));
    }
    // The document with this buffer embedded.
    std::string text(json doc) const {
        doc["asset"] = {{"version", "2.0"}};
        doc["buffers"] = {
            {{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + gltftest::base64(bytes)}}};
        doc["bufferViews"] = views;
        return doc.dump();
    }
};

json accessor(int view, int componentType, const char* type, size_t count) {
    return {{"bufferView", view}, {"componentType", componentType}, {"type", type}, {"count", count}};
}

// A 2x2 PNG: red channel 0, 1 / 255, 1 (feature ids), green 40, 80 / 120, 160 (a property), rows top to bottom.
std::string png2x2() {
    const std::string path = tempPath("2x2.png");
    savePng(path, Image{2, 2, {0, 40, 0, 255, 1, 80, 0, 255, 255, 120, 0, 255, 1, 160, 0, 255}});
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

// Two triangles (vertices 0-2: feature 0, 3-5: feature 1) with four feature ID sets: _FEATURE_ID_0 (UNSIGNED_BYTE,
// property table 0, label "buildings"), implicit, a texture set (null id 255), _FEATURE_ID_1 (FLOAT, null id 7);
// a property texture and a property attribute (_TEMPERATURE). Class building: height FLOAT32, name STRING, floors
// UINT8, kind ENUM; rows: (12.5, "Hall", 3, commercial), (30.25, "Tower", 10, residential). With `instanced`, a
// second node places the mesh 3 times with EXT_instance_features (ids 1, 0, 1 over the table; implicit).
std::string featuresDoc(bool instanced = false, const std::function<void(json&)>& edit = {}) {
    Bin bin;
    json acc = json::array();
    const std::vector<float> pos{0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 2, 1, 0};
    acc.push_back(accessor(bin.add(pos), 5126, "VEC3", 6));
    acc[0]["min"] = {0, 0, 0};
    acc[0]["max"] = {3, 1, 0};
    const std::vector<float> uv{0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.75f, 0.25f, 0.75f, 0.25f, 0.75f, 0.25f};
    acc.push_back(accessor(bin.add(uv), 5126, "VEC2", 6));
    acc.push_back(accessor(bin.add(std::vector<uint8_t>{0, 0, 0, 1, 1, 1}), 5121, "SCALAR", 6));
    acc.push_back(accessor(bin.add(std::vector<float>{0, 0, 0, 7, 7, 7}), 5126, "SCALAR", 6));
    acc.push_back(accessor(bin.add(std::vector<float>{10, 11, 12, 13, 14, 15}), 5126, "SCALAR", 6));
    const int height = bin.add(std::vector<float>{12.5f, 30.25f});
    const int names = bin.raw("HallTower", 9);
    const int nameOffsets = bin.add(std::vector<uint32_t>{0, 4, 9});
    const int floors = bin.add(std::vector<uint8_t>{3, 10});
    const int kind = bin.add(std::vector<uint16_t>{1, 0});
    json doc;
    if (instanced) {
        acc.push_back(accessor(bin.add(std::vector<float>{0, 0, 0, 10, 0, 0, 20, 0, 0}), 5126, "VEC3", 3));
        acc.push_back(accessor(bin.add(std::vector<float>{1, 0, 1}), 5126, "SCALAR", 3));
        doc["nodes"][1] = {
            {"mesh", 0},
            {"extensions",
             {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", 5}, {"_FEATURE_ID_0", 6}}}}},
              {"EXT_instance_features",
               {{"featureIds",
                 {{{"featureCount", 2}, {"attribute", 0}, {"propertyTable", 0}}, {{"featureCount", 3}}}}}}}}};
        doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing", "EXT_instance_features"};
    }
    doc["accessors"] = acc;
    doc["nodes"][0] = {{"mesh", 0}};
    doc["scenes"] = {{{"nodes", instanced ? json{0, 1} : json{0}}}};
    doc["scene"] = 0;
    doc["images"] = {{{"uri", "data:image/png;base64," + gltftest::base64(png2x2())}}};
    doc["textures"] = {{{"source", 0}}};
    const json featureIds = {
        {{"featureCount", 2}, {"attribute", 0}, {"propertyTable", 0}, {"label", "buildings"}},
        {{"featureCount", 6}},
        {{"featureCount", 2}, {"nullFeatureId", 255}, {"texture", {{"index", 0}, {"texCoord", 0}, {"channels", {0}}}}},
        {{"featureCount", 1}, {"nullFeatureId", 7}, {"attribute", 1}}};
    json primitive;
    primitive["attributes"] = {
        {"POSITION", 0}, {"TEXCOORD_0", 1}, {"_FEATURE_ID_0", 2}, {"_FEATURE_ID_1", 3}, {"_TEMPERATURE", 4}};
    primitive["extensions"]["EXT_mesh_features"]["featureIds"] = featureIds;
    primitive["extensions"]["EXT_structural_metadata"] = {{"propertyTextures", {0}}, {"propertyAttributes", {0}}};
    doc["meshes"][0]["primitives"][0] = primitive;
    const json schema = {
        {"id", "city"},
        {"enums",
         {{"kind", {{"values", {{{"name", "residential"}, {"value", 0}}, {{"name", "commercial"}, {"value", 1}}}}}}}},
        {"classes",
         {{"building",
           {{"properties",
             {{"height", {{"type", "SCALAR"}, {"componentType", "FLOAT32"}}},
              {"name", {{"type", "STRING"}}},
              {"floors", {{"type", "SCALAR"}, {"componentType", "UINT8"}}},
              {"kind", {{"type", "ENUM"}, {"enumType", "kind"}}}}}}},
          {"temp", {{"properties", {{"temperature", {{"type", "SCALAR"}, {"componentType", "FLOAT32"}}}}}}},
          {"surface",
           {{"properties",
             {{"roughness", {{"type", "SCALAR"}, {"componentType", "UINT8"}}}, {"label", {{"type", "STRING"}}}}}}}}}};
    doc["extensions"]["EXT_structural_metadata"] = {
        {"schema", schema},
        {"propertyTables",
         {{{"class", "building"},
           {"count", 2},
           {"properties",
            {{"height", {{"values", height}}},
             {"name", {{"values", names}, {"stringOffsets", nameOffsets}}},
             {"floors", {{"values", floors}}},
             {"kind", {{"values", kind}}}}}}}},
        {"propertyTextures",
         {{{"class", "surface"},
           {"properties",
            {{"roughness", {{"index", 0}, {"channels", {1}}}}, {"label", {{"index", 0}, {"channels", {0}}}}}}}}},
        {"propertyAttributes",
         {{{"class", "temp"}, {"properties", {{"temperature", {{"attribute", "_TEMPERATURE"}}}}}}}}};
    doc["extensionsUsed"].push_back("EXT_mesh_features");
    doc["extensionsUsed"].push_back("EXT_structural_metadata");
    if (edit) edit(doc);
    return bin.text(doc);
}

GltfScene load(const std::string& text, const GltfLoadOptions& options = {}) {
    return loadGltfFromMemory("features.gltf", text.data(), text.size(), options);
}

void collect(const Node& n, std::vector<const Geometry*>& geometries, std::vector<const Instance*>& instances) {
    if (n.kind() == NodeKind::Geometry) geometries.push_back(static_cast<const Geometry*>(&n));
    if (n.kind() == NodeKind::Instance) {
        instances.push_back(static_cast<const Instance*>(&n));
        return;  // the prototype is the plain node's Geometry
    }
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (n.child(i)) collect(*n.child(i), geometries, instances);
}

const Mesh& firstMesh(const GltfScene& s) {
    std::vector<const Geometry*> g;
    std::vector<const Instance*> in;
    collect(*s.root, g, in);
    EXPECT_FALSE(g.empty());
    return *g.at(0)->mesh();
}

std::vector<const Instance*> instances(const GltfScene& s) {
    std::vector<const Geometry*> g;
    std::vector<const Instance*> in;
    collect(*s.root, g, in);
    return in;
}

}  // namespace

TEST(GltfFeatures, ReadsTheFeatureIdSetsOfAPrimitive) {
    const GltfScene s = load(featuresDoc());
    const Mesh& mesh = firstMesh(s);
    EXPECT_EQ(mesh.source().file, "features.gltf");
    EXPECT_EQ(mesh.source().gltfMesh, 0);
    EXPECT_EQ(mesh.source().gltfPrimitive, 0);
    const MeshFeatures* f = mesh.features();
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(f->sets.size(), 4u);
    const FeatureIdSet& a = f->sets[0];
    EXPECT_EQ(a.source, FeatureIdSet::Source::Attribute);
    EXPECT_EQ(a.label, "buildings");
    EXPECT_EQ(a.featureCount, 2u);
    EXPECT_EQ(a.propertyTable, 0);
    EXPECT_FALSE(a.hasNullFeatureId);
    EXPECT_EQ(a.ids, (std::vector<uint32_t>{0, 0, 0, 1, 1, 1}));
    EXPECT_EQ(f->sets[1].source, FeatureIdSet::Source::Implicit);
    EXPECT_EQ(f->sets[1].featureCount, 6u);
    EXPECT_EQ(f->sets[1].propertyTable, -1);
    const FeatureIdSet& t = f->sets[2];
    EXPECT_EQ(t.source, FeatureIdSet::Source::Texture);
    ASSERT_TRUE(t.texture);
    EXPECT_EQ(t.texture->width(), 2);
    EXPECT_EQ(t.texture->height(), 2);
    EXPECT_EQ(t.texture->rgba()[8], 255);  // texel (0, 1)'s red: the null id
    EXPECT_EQ(t.channels, (std::vector<uint8_t>{0}));
    EXPECT_EQ(t.texCoord, 0);
    EXPECT_TRUE(t.hasNullFeatureId);
    EXPECT_EQ(t.nullFeatureId, 255u);
    const FeatureIdSet& fl = f->sets[3];  // FLOAT ids made whole numbers
    EXPECT_EQ(fl.ids, (std::vector<uint32_t>{0, 0, 0, 7, 7, 7}));
    EXPECT_TRUE(fl.hasNullFeatureId);
    EXPECT_EQ(fl.nullFeatureId, 7u);
}

TEST(GltfFeatures, ReadsThePropertyTableRows) {
    const GltfScene s = load(featuresDoc());
    const MeshFeatures* f = firstMesh(s).features();
    ASSERT_NE(f, nullptr);
    ASSERT_TRUE(f->store);
    const PropertyStore& store = *f->store;
    ASSERT_EQ(store.tables().size(), 1u);
    EXPECT_EQ(store.tables()[0].count, 2u);
    const int cls = store.schema.findClass("building");
    ASSERT_GE(cls, 0);
    const ClassDef& c = store.schema.classes[size_t(cls)];
    const int height = c.find("height"), name = c.find("name"), floors = c.find("floors"), kind = c.find("kind");
    // Vertex 4 is feature 1: the second row.
    const uint32_t row = f->sets[0].ids[4];
    EXPECT_EQ(row, 1u);
    EXPECT_DOUBLE_EQ(store.value(0, row, height).asNumber(), 30.25);
    EXPECT_EQ(store.value(0, row, name).string, "Tower");
    EXPECT_DOUBLE_EQ(store.value(0, row, floors).asNumber(), 10.0);
    EXPECT_EQ(store.value(0, row, kind).string, "residential");
    EXPECT_DOUBLE_EQ(store.value(0, 0, height).asNumber(), 12.5);
    EXPECT_EQ(store.value(0, 0, name).string, "Hall");
    EXPECT_DOUBLE_EQ(store.value(0, 0, floors).asNumber(), 3.0);
    EXPECT_EQ(store.value(0, 0, kind).string, "commercial");
}

TEST(GltfFeatures, ReadsPropertyTexturesAndAttributes) {
    const GltfScene s = load(featuresDoc());
    const MeshFeatures* f = firstMesh(s).features();
    ASSERT_NE(f, nullptr);
    ASSERT_TRUE(f->store);
    ASSERT_EQ(f->store->propertyTextures.size(), 1u);
    EXPECT_EQ(f->propertyTextures, (std::vector<int>{0}));
    // The STRING property cannot be in a texture: left out with a warning naming it.
    const PropertyTextureDef& tex = f->store->propertyTextures[0];
    ASSERT_EQ(tex.properties.size(), 1u);
    EXPECT_EQ(tex.properties[0].channels, (std::vector<uint8_t>{1}));
    EXPECT_TRUE(tex.properties[0].texture);
    bool warned = false;
    for (const std::string& w : s.warnings)
        warned |= w.rfind("extensions.EXT_structural_metadata.propertyTextures[0].properties.label:", 0) == 0;
    EXPECT_TRUE(warned);
    ASSERT_EQ(f->propertyAttributes.size(), 1u);
    const PropertyAttributeValues& a = f->propertyAttributes[0];
    EXPECT_EQ(a.propertyAttribute, 0);
    ASSERT_EQ(a.columns.size(), 1u);
    EXPECT_EQ(a.columns[0].stride, 4u);
    ASSERT_EQ(a.columns[0].bytes.size(), 24u);
    float v = 0;
    std::memcpy(&v, a.columns[0].bytes.data() + 4 * 4, 4);
    EXPECT_EQ(v, 14.0f);
}

TEST(GltfFeatures, InstancesShareTheNodesInstanceFeatures) {
    const GltfScene s = load(featuresDoc(true));
    const std::vector<const Instance*> in = instances(s);
    ASSERT_EQ(in.size(), 3u);
    const MeshFeatures* f = in[0]->features();
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(f->sets.size(), 2u);
    EXPECT_EQ(f->sets[0].source, FeatureIdSet::Source::Instance);
    EXPECT_EQ(f->sets[0].propertyTable, 0);
    EXPECT_EQ(f->sets[1].ids, (std::vector<uint32_t>{0, 1, 2}));  // implicit: the instance index
    for (const Instance* i : in) {
        EXPECT_EQ(i->features(), f);
        const double x = i->matrix()[3][0];
        const uint32_t want = x == 10.0 ? 0u : 1u;  // ids 1, 0, 1 at x = 0, 10, 20
        EXPECT_EQ(f->sets[0].ids.at(i->featureIndex()), want) << "x " << x;
    }
}

TEST(GltfFeatures, PrimitivesWithOtherFeaturesDoNotShareAMesh) {
    const GltfScene s = load(featuresDoc(false, [](json& d) {
        json plain = d["meshes"][0]["primitives"][0];
        plain.erase("extensions");
        d["meshes"][0]["primitives"].push_back(plain);
    }));
    std::vector<const Geometry*> g;
    std::vector<const Instance*> in;
    collect(*s.root, g, in);
    ASSERT_EQ(g.size(), 2u);
    EXPECT_NE(g[0]->mesh(), g[1]->mesh());
    EXPECT_NE(g[0]->mesh()->features(), nullptr);
    EXPECT_EQ(g[1]->mesh()->features(), nullptr);
    EXPECT_EQ(g[1]->mesh()->source().gltfPrimitive, 1);
}

TEST(GltfFeatures, RoundTripKeepsSetsAndValues) {
    const GltfScene a = load(featuresDoc(true));
    const std::string path = tempPath("roundtrip.gltf");
    std::vector<std::string> warnings;
    GltfSaveOptions options;
    options.warnings = &warnings;
    saveGltf(*a.root, path, options);
    const GltfScene b = loadGltf(path);
    const MeshFeatures* fa = firstMesh(a).features();
    const MeshFeatures* fb = firstMesh(b).features();
    ASSERT_NE(fa, nullptr);
    ASSERT_NE(fb, nullptr);
    ASSERT_EQ(fb->sets.size(), fa->sets.size());
    for (size_t k = 0; k < fa->sets.size(); ++k) {
        SCOPED_TRACE(k);
        const FeatureIdSet &x = fa->sets[k], &y = fb->sets[k];
        EXPECT_EQ(y.source, x.source);
        EXPECT_EQ(y.label, x.label);
        EXPECT_EQ(y.featureCount, x.featureCount);
        EXPECT_EQ(y.hasNullFeatureId, x.hasNullFeatureId);
        EXPECT_EQ(y.nullFeatureId, x.nullFeatureId);
        EXPECT_EQ(y.propertyTable, x.propertyTable);
        EXPECT_EQ(y.ids, x.ids);
        EXPECT_EQ(y.channels, x.channels);
        EXPECT_EQ(y.texCoord, x.texCoord);
        EXPECT_EQ(bool(y.texture), bool(x.texture));
        if (x.texture && y.texture) {
            EXPECT_EQ(y.texture->rgba(), x.texture->rgba());
        }
    }
    ASSERT_TRUE(fb->store);
    const PropertyStore &sa = *fa->store, &sb = *fb->store;
    ASSERT_EQ(sb.tables().size(), sa.tables().size());
    for (size_t t = 0; t < sa.tables().size(); ++t) {
        ASSERT_EQ(sb.tables()[t].count, sa.tables()[t].count);
        const ClassDef& cls = sa.schema.classes[size_t(sa.tables()[t].classIndex)];
        for (uint64_t r = 0; r < sa.tables()[t].count; ++r)
            for (size_t p = 0; p < cls.properties.size(); ++p)
                EXPECT_EQ(sb.value(int(t), r, int(p)), sa.value(int(t), r, int(p))) << cls.properties[p].id << " " << r;
    }
    // Instances: each keeps its id.
    const std::vector<const Instance*> ia = instances(a), ib = instances(b);
    ASSERT_EQ(ib.size(), ia.size());
    for (const Instance* i : ib) {
        ASSERT_NE(i->features(), nullptr);
        const double x = i->matrix()[3][0];
        EXPECT_EQ(i->features()->sets.at(0).ids.at(i->featureIndex()), x == 10.0 ? 0u : 1u) << "x " << x;
        EXPECT_EQ(i->features()->sets.at(0).propertyTable, 0);
    }
    // What the writer leaves out is said.
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("property textures and property attributes are not written"), std::string::npos);
}

// A triangle with a _BATCHID attribute (ids 0, 1, 1) and no EXT_mesh_features: a 3D Tiles 1.0 tile's glTF.
std::string batchedDoc() {
    Bin bin;
    json doc;
    doc["accessors"] = {accessor(bin.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}), 5126, "VEC3", 3),
                        accessor(bin.add(std::vector<uint16_t>{0, 1, 1, 0}), 5123, "SCALAR", 3)};
    doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"_BATCHID", 1}}}}}}}};
    doc["nodes"] = {{{"mesh", 0}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    return bin.text(doc);
}

TEST(GltfFeatures, BatchIdsNameRowsOfTheGivenBatchTable) {
    auto store = make<PropertyStore>();
    ClassDef cls;
    cls.id = "batch";
    ClassProperty height;
    height.id = "height";
    height.type = PropertyType::Scalar;
    height.componentType = ComponentType::Float32;
    cls.properties.push_back(height);
    store->schema.classes.push_back(cls);
    const float heights[2] = {5.0f, 7.0f};
    const int buffer = store->addBuffer(
        std::vector<uint8_t>(reinterpret_cast<const uint8_t*>(heights), reinterpret_cast<const uint8_t*>(heights) + 8));
    PropertyTable table;
    table.classIndex = 0;
    table.count = 2;
    PropertyColumn column;
    column.property = 0;
    column.values = ByteSpan{buffer, 0, 8};
    table.columns.push_back(column);
    store->addTable(table);

    EXPECT_EQ(firstMesh(load(batchedDoc())).features(), nullptr);  // without a batch table: plain glTF
    GltfLoadOptions options;
    options.batchTable = store;
    const GltfScene s = load(batchedDoc(), options);
    const MeshFeatures* f = firstMesh(s).features();
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(f->sets.size(), 1u);
    const FeatureIdSet& set = f->sets[0];
    EXPECT_EQ(set.source, FeatureIdSet::Source::Attribute);
    EXPECT_EQ(set.ids, (std::vector<uint32_t>{0, 1, 1}));
    EXPECT_EQ(set.label, "");
    EXPECT_EQ(set.propertyTable, 0);
    EXPECT_EQ(set.featureCount, 2u);
    EXPECT_EQ(f->store.get(), store.get());
    EXPECT_DOUBLE_EQ(f->store->value(0, set.ids[2], 0).asNumber(), 7.0);
}

TEST(GltfFeatures, BadInputNamesItsPath) {
    const std::string prim = "meshes[0].primitives[0]";
    const std::string ids = prim + ".extensions.EXT_mesh_features.featureIds";
    const std::string root = "extensions.EXT_structural_metadata";
    auto featureId = [](json& d) -> json& {
        return d["meshes"][0]["primitives"][0]["extensions"]["EXT_mesh_features"]["featureIds"];
    };
    const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
        {[](json& d) { d["accessors"][2]["count"] = 5; }, prim + ".attributes._FEATURE_ID_0"},
        {[&](json& d) { featureId(d)[0]["propertyTable"] = 5; }, ids + "[0].propertyTable"},
        {[&](json& d) { featureId(d)[0]["featureCount"] = 0; }, ids + "[0].featureCount"},
        {[&](json& d) { featureId(d)[0]["attribute"] = 9; }, ids + "[0].attribute"},
        {[&](json& d) { featureId(d)[2]["texture"]["index"] = 3; }, ids + "[2].texture.index"},
        {[&](json& d) { featureId(d)[2]["texture"]["channels"] = {4}; }, ids + "[2].texture.channels[0]"},
        {[&](json& d) {
             d["extensions"]["EXT_structural_metadata"]["propertyAttributes"][0]["properties"]["temperature"]
              ["attribute"] = "_HUMIDITY";
         },
         prim + ".extensions.EXT_structural_metadata.propertyAttributes[0]"},
        {[](json& d) { d["accessors"][4]["componentType"] = 5125; }, prim + ".attributes._TEMPERATURE"},
        {[](json& d) {
             d["extensions"]["EXT_structural_metadata"]["propertyTextures"][0]["properties"]["roughness"]["index"] = 7;
         },
         root + ".propertyTextures[0].properties.roughness.index"},
    };
    for (const auto& [edit, path] : cases) {
        SCOPED_TRACE(path);
        try {
            load(featuresDoc(false, edit));
            ADD_FAILURE() << "loaded";
        } catch (const LoadError& e) {
            EXPECT_EQ(e.jsonPath(), path) << e.what();
        }
    }
}

// Nodes that are features over a shared mesh (a city's buildings): saveGltf keeps each binding (sgkit's extras:
// glTF has none for a plain node), and the nodes read back name the same rows of the same values.
TEST(GltfFeatures, NodesThatAreFeaturesKeepTheirRowsThroughARoundTrip) {
    auto store = make<PropertyStore>();
    PropertyTableBuilder b("building", "buildings");
    b.addScalar("height", ComponentType::Float64);
    b.addString("name");
    for (int i = 0; i < 5; ++i)
        b.addRow({PropertyValue::ofNumber(10.0 + i), PropertyValue::ofString("house " + std::to_string(i))});
    const int table = b.finish(*store);
    const ref_ptr<MeshFeatures> sets = rowFeatures(store, table, "building");
    auto mesh = makeBoxMesh(dvec3(-1), dvec3(1));
    auto root = make<Group>();
    for (uint32_t i : {3u, 0u, 4u}) {  // rows out of order
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(3.0 * i, 0, 0)));
        t->addChild(make<Geometry>(mesh, make<Material>()));
        t->setFeatures(sets, i);
        root->addChild(t);
    }
    const std::string path = tempPath("node_features.glb");
    saveGltf(*root, path);
    const GltfScene back = loadGltf(path);
    std::vector<std::pair<double, std::string>> got;  // each feature node's row: height and name, by x
    std::function<void(const Node&)> walk = [&](const Node& n) {
        if (const MeshFeatures* f = n.features()) {
            ASSERT_TRUE(f->store);
            const int64_t id = f->idAt(0, n.featureIndex());
            EXPECT_EQ(f->sets[0].label, "building");
            const int t = f->sets[0].propertyTable;
            const ClassDef& cls = f->store->schema.classes[size_t(f->store->tables()[size_t(t)].classIndex)];
            got.emplace_back(f->store->value(t, uint64_t(id), cls.find("height")).number,
                             f->store->value(t, uint64_t(id), cls.find("name")).string);
        }
        for (size_t i = 0; i < n.numChildren(); ++i) walk(*n.child(i));
    };
    walk(*back.root);
    ASSERT_EQ(got.size(), 3u);
    EXPECT_EQ(got[0], std::make_pair(13.0, std::string("house 3")));
    EXPECT_EQ(got[1], std::make_pair(10.0, std::string("house 0")));
    EXPECT_EQ(got[2], std::make_pair(14.0, std::string("house 4")));
}
