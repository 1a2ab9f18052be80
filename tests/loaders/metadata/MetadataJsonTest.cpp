// The metadata JSON reader: a schema of every type read into its fields and written back equal; bad schemas refused
// with the JSON path at fault; a property table's columns with their buffer views.
#include "loaders/metadata/internal/MetadataJson.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

using namespace sg;
using namespace sg::metadata;
using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

namespace {

const char* kSchema = R"({
  "id": "city", "name": "City", "version": "1.0",
  "enums": {"kind": {"valueType": "UINT8", "values": [{"name": "Unknown", "value": 0}, {"name": "House", "value": 1}]}},
  "classes": {"building": {"name": "Building", "description": "A house", "properties": {
    "height": {"type": "SCALAR", "componentType": "FLOAT32", "offset": 1.5, "scale": 2, "noData": -1,
               "default": 0, "required": true},
    "pos": {"type": "VEC3", "componentType": "FLOAT64", "min": [0, 0, 0], "max": [1, 1, 1]},
    "m": {"type": "MAT2", "componentType": "INT16", "normalized": true, "scale": [1, 2, 3, 4]},
    "name": {"type": "STRING", "noData": "", "default": "none"},
    "lit": {"type": "BOOLEAN", "default": true},
    "kind": {"type": "ENUM", "enumType": "kind", "noData": "Unknown"},
    "tags": {"type": "STRING", "array": true},
    "pair": {"type": "SCALAR", "componentType": "UINT8", "array": true, "count": 2, "noData": [0, 0]},
    "big": {"type": "SCALAR", "componentType": "UINT64", "noData": 18446744073709551615}
  }}}
})";

Schema parse(const json& j, std::vector<std::string>* warnings = nullptr) {
    return parseSchema(j, Context{"test.json", warnings}, "schema");
}

const ClassProperty& property(const Schema& s, const std::string& id) {
    const ClassDef& c = s.classes.at(0);
    const int i = c.find(id);
    EXPECT_GE(i, 0) << id;
    return c.properties.at(size_t(i));
}

TEST(MetadataJson, SchemaOfEveryType) {
    const Schema s = parse(json::parse(kSchema));
    EXPECT_EQ(s.id, "city");
    EXPECT_EQ(s.version, "1.0");
    ASSERT_EQ(s.enums.size(), 1u);
    EXPECT_EQ(s.enums[0].valueType, ComponentType::UInt8);
    ASSERT_EQ(s.enums[0].values.size(), 2u);
    EXPECT_EQ(s.enums[0].values[1], (std::pair<std::string, int64_t>("House", 1)));
    ASSERT_EQ(s.classes.size(), 1u);
    EXPECT_EQ(s.classes[0].name, "Building");
    EXPECT_EQ(s.classes[0].properties.size(), 9u);

    const ClassProperty& height = property(s, "height");
    EXPECT_EQ(height.type, PropertyType::Scalar);
    EXPECT_EQ(height.componentType, ComponentType::Float32);
    EXPECT_TRUE(height.required);
    EXPECT_EQ(height.offset, PropertyValue::ofNumber(1.5));
    EXPECT_EQ(height.scale, PropertyValue::ofInt(2));
    EXPECT_EQ(height.noData, PropertyValue::ofInt(-1));
    EXPECT_EQ(property(s, "pos").max.items.size(), 3u);
    EXPECT_TRUE(property(s, "m").normalized);
    EXPECT_EQ(property(s, "m").type, PropertyType::Mat2);
    EXPECT_EQ(property(s, "name").defaultValue, PropertyValue::ofString("none"));
    EXPECT_EQ(property(s, "lit").defaultValue, PropertyValue::ofBool(true));
    const ClassProperty& kind = property(s, "kind");
    EXPECT_EQ(kind.enumIndex, 0);
    EXPECT_EQ(kind.componentType, ComponentType::UInt8);  // the enum's value type
    EXPECT_EQ(kind.noData, PropertyValue::ofString("Unknown"));
    EXPECT_TRUE(property(s, "tags").array);
    EXPECT_EQ(property(s, "tags").count, 0u);
    EXPECT_EQ(property(s, "pair").count, 2u);
    EXPECT_EQ(property(s, "big").noData, PropertyValue::ofUInt(UINT64_MAX));
}

void expectSameProperty(const ClassProperty& a, const ClassProperty& b) {
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.description, b.description);
    EXPECT_EQ(a.type, b.type) << a.id;
    EXPECT_EQ(a.componentType, b.componentType) << a.id;
    EXPECT_EQ(a.enumIndex, b.enumIndex) << a.id;
    EXPECT_EQ(a.array, b.array) << a.id;
    EXPECT_EQ(a.count, b.count) << a.id;
    EXPECT_EQ(a.normalized, b.normalized) << a.id;
    EXPECT_EQ(a.required, b.required) << a.id;
    for (auto m : {&ClassProperty::offset, &ClassProperty::scale, &ClassProperty::min, &ClassProperty::max,
                   &ClassProperty::noData, &ClassProperty::defaultValue})
        EXPECT_EQ(a.*m, b.*m) << a.id << ": " << (a.*m).toJson() << " vs " << (b.*m).toJson();
}

TEST(MetadataJson, SchemaJsonReadsBackEqual) {
    const Schema s = parse(json::parse(kSchema));
    const Schema back = parse(schemaJson(s));
    EXPECT_EQ(back.id, s.id);
    EXPECT_EQ(back.name, s.name);
    EXPECT_EQ(back.version, s.version);
    ASSERT_EQ(back.enums.size(), s.enums.size());
    EXPECT_EQ(back.enums[0].id, s.enums[0].id);
    EXPECT_EQ(back.enums[0].valueType, s.enums[0].valueType);
    EXPECT_EQ(back.enums[0].values, s.enums[0].values);
    ASSERT_EQ(back.classes.size(), 1u);
    EXPECT_EQ(back.classes[0].id, "building");
    EXPECT_EQ(back.classes[0].description, "A house");
    ASSERT_EQ(back.classes[0].properties.size(), s.classes[0].properties.size());
    for (size_t i = 0; i < s.classes[0].properties.size(); ++i)
        expectSameProperty(back.classes[0].properties[i], s.classes[0].properties[i]);
    EXPECT_EQ(schemaJson(back), schemaJson(s));
}

// The schema with one property of `building` replaced by `p`: parseSchema throws LoadError at `path`.
void expectBadProperty(const json& p, const std::string& path) {
    json j = json::parse(kSchema);
    j["classes"]["building"]["properties"]["height"] = p;
    try {
        parse(j);
        ADD_FAILURE() << "accepted: " << p.dump();
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath(), "schema.classes.building.properties.height." + path) << e.what();
        EXPECT_EQ(e.file(), "test.json");
    }
}

TEST(MetadataJson, BadSchemasNameThePath) {
    expectBadProperty({{"type", "VEC5"}, {"componentType", "FLOAT32"}}, "type");
    expectBadProperty({{"type", "SCALAR"}, {"componentType", "FLOAT16"}}, "componentType");
    expectBadProperty({{"type", "SCALAR"}}, "componentType");
    expectBadProperty({{"type", "ENUM"}}, "enumType");
    expectBadProperty({{"type", "ENUM"}, {"enumType", "colour"}}, "enumType");
    expectBadProperty({{"type", "VEC3"}, {"componentType", "FLOAT32"}, {"noData", 5}}, "noData");
    expectBadProperty({{"type", "VEC3"}, {"componentType", "FLOAT32"}, {"noData", {1, 2}}}, "noData");
    expectBadProperty({{"type", "SCALAR"}, {"componentType", "FLOAT32"}, {"normalized", true}}, "normalized");
    expectBadProperty({{"type", "SCALAR"}, {"componentType", "INT32"}, {"offset", 1}}, "offset");
    expectBadProperty({{"type", "SCALAR"}, {"componentType", "INT32"}, {"array", true}, {"count", 1}}, "count");
    expectBadProperty({{"type", "ENUM"}, {"enumType", "kind"}, {"default", "Castle"}}, "default");
    expectBadProperty({{"type", "BOOLEAN"}, {"noData", false}}, "noData");
    expectBadProperty(
        {{"type", "SCALAR"}, {"componentType", "UINT8"}, {"array", true}, {"count", 2}, {"noData", {1, 2, 3}}},
        "noData");
}

// A view index v is bytes [10 v, 10 v + 10) of buffer 0; index 9 and up do not exist.
ByteSpan lookup(int64_t v, const std::string& path) {
    if (v < 0 || v >= 9) throw LoadError("test.json", path, "no bufferView " + std::to_string(v));
    return ByteSpan{0, uint64_t(v) * 10, 10};
}

TEST(MetadataJson, PropertyTableWithViews) {
    const Schema s = parse(json::parse(kSchema));
    std::vector<std::string> warnings;
    const Context c{"test.json", &warnings};
    const json t = json::parse(R"({"name": "t0", "class": "building", "count": 2, "properties": {
        "height": {"values": 0, "offset": 5},
        "name": {"values": 1, "stringOffsets": 2, "stringOffsetType": "UINT16"},
        "tags": {"values": 3, "stringOffsets": 4, "arrayOffsets": 5, "arrayOffsetType": "UINT8"},
        "extra": {"values": 6}}})");
    const PropertyTable table = parsePropertyTable(t, s, lookup, c, "t");
    EXPECT_EQ(table.name, "t0");
    EXPECT_EQ(table.classIndex, 0);
    EXPECT_EQ(table.count, 2u);
    ASSERT_EQ(table.columns.size(), 3u);
    const PropertyColumn* height = table.column(s.classes[0].find("height"));
    ASSERT_NE(height, nullptr);
    EXPECT_EQ(height->values.offset, 0u);
    EXPECT_EQ(height->overrides.offset, PropertyValue::ofInt(5));
    const PropertyColumn* name = table.column(s.classes[0].find("name"));
    ASSERT_NE(name, nullptr);
    EXPECT_EQ(name->stringOffsets.offset, 20u);
    EXPECT_EQ(name->stringOffsetType, ComponentType::UInt16);
    const PropertyColumn* tags = table.column(s.classes[0].find("tags"));
    ASSERT_NE(tags, nullptr);
    EXPECT_EQ(tags->arrayOffsets.offset, 50u);
    EXPECT_EQ(tags->arrayOffsetType, ComponentType::UInt8);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("t.properties.extra"), std::string::npos) << warnings[0];
}

void expectBadTable(const char* text, const std::string& path) {
    const Schema s = parse(json::parse(kSchema));
    try {
        parsePropertyTable(json::parse(text), s, lookup, Context{"test.json", nullptr}, "t");
        ADD_FAILURE() << "accepted: " << text;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath(), path) << e.what();
    }
}

TEST(MetadataJson, BadPropertyTables) {
    expectBadTable(R"({"class": "building", "count": 1, "properties": {}})", "t.properties.height");  // required
    expectBadTable(R"({"class": "tree", "count": 1})", "t.class");
    expectBadTable(R"({"class": "building", "count": -1})", "t.count");
    expectBadTable(R"({"class": "building", "count": 1, "properties": {"height": {"values": 12}}})",
                   "t.properties.height.values");
    expectBadTable(R"({"class": "building", "count": 1, "properties": {"height": {"values": 0},
                       "name": {"values": 1}}})",
                   "t.properties.name.stringOffsets");
    expectBadTable(R"({"class": "building", "count": 1, "properties": {"height": {"values": 0},
                       "pair": {"values": 1, "offset": [1, 2]}}})",
                   "t.properties.pair.offset");
    expectBadTable(R"({"class": "building", "count": 1, "properties": {"height": {"values": 0,
                       "arrayOffsetType": "FLOAT32"}}})",
                   "t.properties.height.arrayOffsetType");
}

TEST(MetadataJson, ValuesBothWays) {
    EXPECT_EQ(valueOf(json(5)).kind, PropertyValue::Kind::Integer);
    EXPECT_EQ(valueOf(json(-5)), PropertyValue::ofInt(-5));
    EXPECT_EQ(valueOf(json(UINT64_MAX)).kind, PropertyValue::Kind::Unsigned);
    EXPECT_EQ(valueOf(json(2.5)), PropertyValue::ofNumber(2.5));
    EXPECT_EQ(valueOf(json::parse(R"([true, "a", null])")),
              PropertyValue::ofArray({PropertyValue::ofBool(true), PropertyValue::ofString("a"), PropertyValue()}));
    EXPECT_TRUE(jsonOf(PropertyValue::ofNumber(std::nan(""))).is_null());
    EXPECT_EQ(jsonOf(PropertyValue::ofInt(INT64_MIN)), json(INT64_MIN));
    EXPECT_EQ(jsonOf(PropertyValue::ofArray({PropertyValue::ofString("x")})), json::parse(R"(["x"])"));
}

// The fuzzer's richest seed (fuzz/metadata-corpus/every-type: JSON, a NUL, the buffer) reads as it was written:
// the fuzzer starts from input that gets past addTable.
TEST(MetadataJson, TheFuzzSeedReads) {
    std::ifstream in(SGKIT_SOURCE_DIR "/fuzz/metadata-corpus/every-type", std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
    const auto nul = std::find(bytes.begin(), bytes.end(), uint8_t(0));
    ASSERT_NE(nul, bytes.end());
    const json j = json::parse(bytes.begin(), nul);
    auto store = make<PropertyStore>();
    const Context c{"every-type", nullptr};
    store->schema = parseSchema(j["schema"], c, "schema");
    store->addBuffer(std::vector<uint8_t>(nul + 1, bytes.end()));
    const json& views = j["bufferViews"];
    const auto view = [&](int64_t v, const std::string&) {
        return ByteSpan{0, views.at(size_t(v))["byteOffset"].get<uint64_t>(),
                        views.at(size_t(v))["byteLength"].get<uint64_t>()};
    };
    const int t = store->addTable(parsePropertyTable(j["propertyTable"], store->schema, view, c, "propertyTable"));
    const ClassDef& cls = store->schema.classes[0];
    const auto at = [&](const char* id, uint64_t row) { return store->value(t, row, cls.find(id)); };
    const auto S = [](const char* s) { return PropertyValue::ofString(s); };
    EXPECT_EQ(at("height", 0), PropertyValue::ofNumber(26));  // 1 + 2 * 12.5
    EXPECT_EQ(at("height", 1), PropertyValue::ofInt(0));      // noData -1: the default
    EXPECT_EQ(at("name", 0), S("ab"));
    EXPECT_EQ(at("name", 1), S("c"));
    EXPECT_EQ(at("lit", 0), PropertyValue::ofBool(true));
    EXPECT_EQ(at("lit", 1), PropertyValue::ofBool(false));
    EXPECT_EQ(at("kind", 0), S("House"));
    EXPECT_TRUE(at("kind", 1).isNull());  // "Unknown" is the noData, and there is no default
    EXPECT_EQ(at("tags", 0), PropertyValue::ofArray({S("x"), S("yz")}));
    EXPECT_EQ(at("tags", 1), PropertyValue::ofArray({}));
    EXPECT_EQ(at("list", 1), PropertyValue::ofArray({PropertyValue::ofInt(5), PropertyValue::ofInt(7)}));
    EXPECT_EQ(at("pair", 0), PropertyValue::ofArray({PropertyValue::ofNumber(0), PropertyValue::ofNumber(2)}));
    EXPECT_EQ(at("pos", 0).toString(), "[0, 0, 0]");  // no column: the default
}

}  // namespace
