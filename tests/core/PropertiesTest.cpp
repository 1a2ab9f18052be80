// PropertyStore reads: every type 3D Tiles 1.1 metadata stores in a property table, from bytes written here, with
// noData, defaults, normalization, offset and scale; decode() of one element; how values print.
#include "sg/core/Properties.h"
#include "tests/core/PropertyTables.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace sg;
using namespace sg::test;
using Kind = PropertyValue::Kind;

namespace {

class PropertiesTest : public ::testing::Test {
protected:
    ref_ptr<PropertyStore> store = make<PropertyStore>();

    // Adds a one-column table; its values are then read with at().
    int add(const ClassProperty& p, uint64_t count, ColumnBytes c) {
        return store->addTable(oneColumn(*store, p, count, std::move(c)));
    }
    PropertyValue at(int t, uint64_t row) const { return store->value(t, row, 0); }
};

TEST_F(PropertiesTest, SignedScalarsAreExactIntegers) {
    const int i8 = add(prop("a", PropertyType::Scalar, ComponentType::Int8), 2, {le<int8_t>({-128, 5})});
    const int i16 = add(prop("b", PropertyType::Scalar, ComponentType::Int16), 1, {le<int16_t>({-32768})});
    const int i32 = add(prop("c", PropertyType::Scalar, ComponentType::Int32), 1, {le<int32_t>({INT32_MIN})});
    const int i64 =
        add(prop("d", PropertyType::Scalar, ComponentType::Int64), 3, {le<int64_t>({INT64_MIN, INT64_MAX, -1})});
    EXPECT_EQ(at(i8, 0).kind, Kind::Integer);
    EXPECT_EQ(at(i8, 0).integer, -128);
    EXPECT_EQ(at(i8, 1).integer, 5);
    EXPECT_EQ(at(i16, 0).integer, -32768);
    EXPECT_EQ(at(i32, 0).integer, INT32_MIN);
    EXPECT_EQ(at(i64, 0).kind, Kind::Integer);
    EXPECT_EQ(at(i64, 0).integer, INT64_MIN);
    EXPECT_EQ(at(i64, 1).integer, INT64_MAX);  // not rounded through a double
    EXPECT_EQ(at(i64, 2).integer, -1);
}

TEST_F(PropertiesTest, UnsignedAndFloatScalars) {
    const int u8 = add(prop("a", PropertyType::Scalar, ComponentType::UInt8), 1, {le<uint8_t>({255})});
    const int u16 = add(prop("b", PropertyType::Scalar, ComponentType::UInt16), 1, {le<uint16_t>({65535})});
    const int u32 = add(prop("c", PropertyType::Scalar, ComponentType::UInt32), 1, {le<uint32_t>({UINT32_MAX})});
    const int u64 = add(prop("d", PropertyType::Scalar, ComponentType::UInt64), 1, {le<uint64_t>({UINT64_MAX})});
    const int f32 = add(prop("e", PropertyType::Scalar, ComponentType::Float32), 1, {le<float>({12.5f})});
    const int f64 = add(prop("f", PropertyType::Scalar, ComponentType::Float64), 1, {le<double>({-0.1})});
    EXPECT_EQ(at(u8, 0).kind, Kind::Unsigned);
    EXPECT_EQ(at(u8, 0).unsignedInteger, 255u);
    EXPECT_EQ(at(u16, 0).unsignedInteger, 65535u);
    EXPECT_EQ(at(u32, 0).unsignedInteger, UINT32_MAX);
    EXPECT_EQ(at(u64, 0).unsignedInteger, UINT64_MAX);
    EXPECT_EQ(at(f32, 0).kind, Kind::Number);
    EXPECT_EQ(at(f32, 0).number, 12.5);
    EXPECT_EQ(at(f64, 0).number, -0.1);
}

TEST_F(PropertiesTest, VectorsAndColumnMajorMatrices) {
    const int v3 = add(prop("v", PropertyType::Vec3, ComponentType::Float32), 2, {le<float>({1, 2, 3, 4, 5, 6})});
    EXPECT_EQ(at(v3, 1), numbers({4, 5, 6}));
    // A MAT2 [[1, 3], [2, 4]] (rows) is stored by columns: 1, 2 then 3, 4; the value keeps the stored order.
    const int m2 = add(prop("m", PropertyType::Mat2, ComponentType::UInt8), 1, {le<uint8_t>({1, 2, 3, 4})});
    const PropertyValue m = at(m2, 0);
    ASSERT_EQ(m.items.size(), 4u);
    EXPECT_EQ(m.items[1].unsignedInteger, 2u);  // column 0, row 1
    EXPECT_EQ(m.items[2].unsignedInteger, 3u);  // column 1, row 0
}

TEST_F(PropertiesTest, StringsIncludingEmptyAndMultiByte) {
    // "Main hall" (9 bytes), "" and "Zürich" (7 bytes: ü is C3 BC).
    const int t = add(prop("name", PropertyType::String), 3,
                      {textBytes("Main hallZ\xC3\xBCrich"), {}, le<uint32_t>({0, 9, 9, 16})});
    EXPECT_EQ(at(t, 0), PropertyValue::ofString("Main hall"));
    EXPECT_EQ(at(t, 1), PropertyValue::ofString(""));
    EXPECT_EQ(at(t, 2), PropertyValue::ofString("Z\xC3\xBCrich"));
}

TEST_F(PropertiesTest, BooleansAreABitstreamLsbFirst) {
    // Rows 0 and 2 true in byte 0; row 9 is byte 1, bit 1.
    const int t = add(prop("flag", PropertyType::Boolean), 10, {le<uint8_t>({0x05, 0x02})});
    EXPECT_EQ(at(t, 0), PropertyValue::ofBool(true));
    EXPECT_EQ(at(t, 1), PropertyValue::ofBool(false));
    EXPECT_EQ(at(t, 2), PropertyValue::ofBool(true));
    EXPECT_EQ(at(t, 8), PropertyValue::ofBool(false));
    EXPECT_EQ(at(t, 9), PropertyValue::ofBool(true));
}

TEST_F(PropertiesTest, EnumsReadByName) {
    store->schema.enums.push_back({"kind", "", ComponentType::UInt16, {{"Unknown", 0}, {"House", 1}, {"Shed", 7}}});
    ClassProperty p = prop("kind", PropertyType::Enum);
    p.enumIndex = 0;
    const int t = add(p, 2, {le<uint16_t>({7, 1})});
    EXPECT_EQ(at(t, 0), PropertyValue::ofString("Shed"));
    EXPECT_EQ(at(t, 1), PropertyValue::ofString("House"));
}

TEST_F(PropertiesTest, FixedAndVariableLengthArrays) {
    ClassProperty fixed = prop("f", PropertyType::Scalar, ComponentType::UInt8);
    fixed.array = true;
    fixed.count = 3;
    const int f = add(fixed, 2, {le<uint8_t>({1, 2, 3, 4, 5, 6})});
    EXPECT_EQ(at(f, 1), ints({4, 5, 6}));

    // Array offsets are element indices, not bytes: rows [-1], [] and [2, 3, -4].
    ClassProperty var = prop("v", PropertyType::Scalar, ComponentType::Int16);
    var.array = true;
    const int v = add(var, 3, {le<int16_t>({-1, 2, 3, -4}), le<uint32_t>({0, 1, 1, 4})});
    EXPECT_EQ(at(v, 0), ints({-1}));
    EXPECT_EQ(at(v, 1), ints({}));
    EXPECT_EQ(at(v, 2), ints({2, 3, -4}));
}

TEST_F(PropertiesTest, ArraysOfStringsIndexTheStringOffsets) {
    // Rows ["a", "bc"] and ["d"]: array offsets (UINT8) count strings, string offsets count bytes.
    ClassProperty p = prop("names", PropertyType::String);
    p.array = true;
    ColumnBytes c{textBytes("abcd"), le<uint8_t>({0, 2, 3}), le<uint32_t>({0, 1, 3, 4})};
    c.arrayOffsetType = ComponentType::UInt8;
    const int t = add(p, 2, c);
    EXPECT_EQ(at(t, 0), PropertyValue::ofArray({PropertyValue::ofString("a"), PropertyValue::ofString("bc")}));
    EXPECT_EQ(at(t, 1), PropertyValue::ofArray({PropertyValue::ofString("d")}));
}

TEST_F(PropertiesTest, ArraysOfBooleansCountBits) {
    const auto T = PropertyValue::ofBool(true), F = PropertyValue::ofBool(false);
    // Variable length: rows [true, false, true] and [true]: bits 1, 0, 1, 1 = 0x0D; offsets are bit indices.
    ClassProperty var = prop("v", PropertyType::Boolean);
    var.array = true;
    const int v = add(var, 2, {le<uint8_t>({0x0D}), le<uint32_t>({0, 3, 4})});
    EXPECT_EQ(at(v, 0), PropertyValue::ofArray({T, F, T}));
    EXPECT_EQ(at(v, 1), PropertyValue::ofArray({T}));
    // Fixed length 2: rows [false, true] and [true, true]: bits 0, 1, 1, 1 = 0x0E.
    ClassProperty fixed = prop("f", PropertyType::Boolean);
    fixed.array = true;
    fixed.count = 2;
    const int f = add(fixed, 2, {le<uint8_t>({0x0E})});
    EXPECT_EQ(at(f, 0), PropertyValue::ofArray({F, T}));
    EXPECT_EQ(at(f, 1), PropertyValue::ofArray({T, T}));
}

TEST_F(PropertiesTest, NormalizedIntegers) {
    ClassProperty u = prop("u", PropertyType::Scalar, ComponentType::UInt8);
    u.normalized = true;
    const int tu = add(u, 2, {le<uint8_t>({255, 0})});
    EXPECT_EQ(at(tu, 0), PropertyValue::ofNumber(1.0));
    EXPECT_EQ(at(tu, 1), PropertyValue::ofNumber(0.0));
    ClassProperty s = prop("s", PropertyType::Scalar, ComponentType::Int8);
    s.normalized = true;
    const int ts = add(s, 2, {le<int8_t>({-128, 127})});
    EXPECT_EQ(at(ts, 0), PropertyValue::ofNumber(-1.0));  // -128 / 127 clamped to -1
    EXPECT_EQ(at(ts, 1), PropertyValue::ofNumber(1.0));
}

TEST_F(PropertiesTest, OffsetAndScaleFromTheClassAndOverriddenByTheColumn) {
    ClassProperty p = prop("h", PropertyType::Scalar, ComponentType::Float32);
    p.offset = PropertyValue::ofNumber(10);
    p.scale = PropertyValue::ofNumber(3);
    const int classOnly = add(p, 1, {le<float>({2})});
    EXPECT_EQ(at(classOnly, 0), PropertyValue::ofNumber(16));  // 10 + 3 * 2
    ColumnBytes c{le<float>({2})};
    c.overrides.offset = PropertyValue::ofNumber(100);
    const int overridden = add(p, 1, c);
    EXPECT_EQ(at(overridden, 0), PropertyValue::ofNumber(106));  // the column's offset, the class's scale

    // Element-wise for a VEC2, after normalization.
    ClassProperty v = prop("v", PropertyType::Vec2, ComponentType::UInt8);
    v.normalized = true;
    v.offset = numbers({1, 2});
    v.scale = numbers({10, 100});
    const int tv = add(v, 1, {le<uint8_t>({255, 0})});
    EXPECT_EQ(at(tv, 0), numbers({11, 2}));
}

TEST_F(PropertiesTest, NoDataGivesTheDefaultOrNull) {
    ClassProperty p = prop("h", PropertyType::Scalar, ComponentType::Int32);
    p.noData = PropertyValue::ofInt(-1);
    p.defaultValue = PropertyValue::ofInt(42);
    const int withDefault = add(p, 2, {le<int32_t>({-1, 5})});
    EXPECT_EQ(at(withDefault, 0), PropertyValue::ofInt(42));
    EXPECT_EQ(at(withDefault, 1), PropertyValue::ofInt(5));
    p.defaultValue = {};
    const int withoutDefault = add(p, 1, {le<int32_t>({-1})});
    EXPECT_TRUE(at(withoutDefault, 0).isNull());

    // A fixed-length array's noData is the whole array.
    ClassProperty a = prop("a", PropertyType::Scalar, ComponentType::UInt8);
    a.array = true;
    a.count = 2;
    a.noData = ints({0, 0});
    const int ta = add(a, 2, {le<uint8_t>({0, 0, 0, 1})});
    EXPECT_TRUE(at(ta, 0).isNull());
    EXPECT_EQ(at(ta, 1), ints({0, 1}));
}

TEST_F(PropertiesTest, RowsPastTheTableAndAbsentColumns) {
    const int t = add(prop("h", PropertyType::Scalar, ComponentType::UInt8), 2, {le<uint8_t>({1, 2})});
    EXPECT_TRUE(at(t, 2).isNull());
    EXPECT_THROW(store->value(t, 0, 1), std::out_of_range);
    EXPECT_THROW(store->value(t + 1, 0, 0), std::out_of_range);

    // A second property without a column reads as its default, in row() too.
    ClassProperty named = prop("label", PropertyType::String);
    named.defaultValue = PropertyValue::ofString("none");
    store->schema.classes[size_t(store->tables()[size_t(t)].classIndex)].properties.push_back(named);
    EXPECT_EQ(store->value(t, 1, 1), PropertyValue::ofString("none"));
    const auto row = store->row(t, 1);
    ASSERT_EQ(row.size(), 2u);
    EXPECT_EQ(row[0].first, "h");
    EXPECT_EQ(row[0].second, PropertyValue::ofUInt(2));
    EXPECT_EQ(row[1].first, "label");
    EXPECT_EQ(row[1].second, PropertyValue::ofString("none"));
}

TEST_F(PropertiesTest, DecodeReadsOneElementWithTheSameTransforms) {
    ClassDef cls;
    cls.id = "texel";
    cls.properties.push_back(prop("id", PropertyType::Scalar, ComponentType::UInt16));
    ClassProperty n = prop("n", PropertyType::Scalar, ComponentType::UInt8);
    n.normalized = true;
    cls.properties.push_back(n);
    ClassProperty pair = prop("pair", PropertyType::Scalar, ComponentType::UInt8);
    pair.array = true;
    pair.count = 2;
    cls.properties.push_back(pair);
    store->schema.classes.push_back(cls);
    const uint8_t texel[] = {0x34, 0x12, 0xFF, 0x00};
    EXPECT_EQ(store->decode(0, 0, texel, 2, {}), PropertyValue::ofUInt(0x1234));
    EXPECT_TRUE(store->decode(0, 0, texel, 1, {}).isNull());  // too short for a UINT16
    PropertyOverrides twice;
    twice.scale = PropertyValue::ofNumber(2);
    EXPECT_EQ(store->decode(0, 1, texel + 2, 1, twice), PropertyValue::ofNumber(2.0));
    EXPECT_EQ(store->decode(0, 2, texel, 2, {}), ints({0x34, 0x12}));
}

TEST(PropertyValueText, ToStringAndToJson) {
    EXPECT_EQ(PropertyValue::ofNumber(12.5).toString(), "12.5");
    EXPECT_EQ(PropertyValue::ofNumber(0.1).toString(), "0.1");
    EXPECT_EQ(PropertyValue::ofBool(true).toString(), "true");
    EXPECT_EQ(PropertyValue::ofString("Main hall").toString(), "Main hall");
    EXPECT_EQ(ints({1, 2, 3}).toString(), "[1, 2, 3]");
    EXPECT_EQ(PropertyValue().toString(), "null");
    EXPECT_EQ(PropertyValue::ofInt(INT64_MIN).toString(), "-9223372036854775808");
    EXPECT_EQ(PropertyValue::ofUInt(UINT64_MAX).toString(), "18446744073709551615");

    EXPECT_EQ(PropertyValue::ofString("Main hall").toJson(), "\"Main hall\"");
    EXPECT_EQ(PropertyValue::ofString("a\"b\\c\n").toJson(), "\"a\\\"b\\\\c\\n\"");
    EXPECT_EQ(PropertyValue::ofString(std::string("\x01", 1)).toJson(), "\"\\u0001\"");
    EXPECT_EQ(ints({1, 2, 3}).toJson(), "[1,2,3]");
    EXPECT_EQ(PropertyValue::ofNumber(std::nan("")).toJson(), "null");
    EXPECT_EQ(PropertyValue::ofNumber(INFINITY).toJson(), "null");
    EXPECT_EQ(PropertyValue::ofBool(false).toJson(), "false");
    EXPECT_EQ(PropertyValue().toJson(), "null");
}

TEST(PropertyValueText, EqualityAndTypeNames) {
    EXPECT_EQ(PropertyValue::ofInt(5), PropertyValue::ofUInt(5));
    EXPECT_NE(PropertyValue::ofInt(-1), PropertyValue::ofUInt(UINT64_MAX));
    EXPECT_NE(PropertyValue::ofInt(5), PropertyValue::ofNumber(5));
    EXPECT_EQ(componentCount(PropertyType::Mat3), 9);
    EXPECT_EQ(componentBytes(ComponentType::Float64), 8);
    EXPECT_EQ(parseComponentType("UINT16"), ComponentType::UInt16);
    EXPECT_FALSE(parseComponentType("FLOAT16").has_value());
    EXPECT_EQ(parsePropertyType("VEC3"), PropertyType::Vec3);
    EXPECT_STREQ(propertyTypeName(PropertyType::Boolean), "BOOLEAN");
}

}  // namespace
