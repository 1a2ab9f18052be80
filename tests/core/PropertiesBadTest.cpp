// PropertyStore::addTable refuses a table a read could not serve, naming the property and the reason, and adds
// nothing then.
#include "sg/core/Properties.h"
#include "tests/core/PropertyTables.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace sg;
using namespace sg::test;

namespace {

// addTable throws std::invalid_argument whose message holds each of `parts`, and the store keeps no table.
void expectRefused(PropertyStore& store, const PropertyTable& table, std::initializer_list<const char*> parts) {
    try {
        store.addTable(table);
        ADD_FAILURE() << "table accepted";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        for (const char* part : parts) EXPECT_NE(what.find(part), std::string::npos) << what;
    }
    EXPECT_TRUE(store.tables().empty());
}

TEST(PropertiesBad, ValuesTooShortForCount) {
    auto store = make<PropertyStore>();
    const auto t =
        oneColumn(*store, prop("height", PropertyType::Scalar, ComponentType::UInt32), 3, {le<uint32_t>({1, 2})});
    expectRefused(*store, t, {"'height'", "too short"});
}

TEST(PropertiesBad, BooleansTooShortForCount) {
    auto store = make<PropertyStore>();
    const auto t = oneColumn(*store, prop("flag", PropertyType::Boolean), 9, {le<uint8_t>({0xFF})});
    expectRefused(*store, t, {"'flag'", "too short"});
}

TEST(PropertiesBad, StringOffsetsNotAscending) {
    auto store = make<PropertyStore>();
    const auto t =
        oneColumn(*store, prop("name", PropertyType::String), 2, {textBytes("hello"), {}, le<uint32_t>({0, 5, 3})});
    expectRefused(*store, t, {"'name'", "not ascending"});
}

TEST(PropertiesBad, LastOffsetPastTheValues) {
    auto store = make<PropertyStore>();
    const auto t =
        oneColumn(*store, prop("name", PropertyType::String), 2, {textBytes("hello"), {}, le<uint32_t>({0, 2, 10})});
    expectRefused(*store, t, {"'name'", "past"});

    ClassProperty var = prop("list", PropertyType::Scalar, ComponentType::UInt16);
    var.array = true;
    // Offsets count elements: 3 UINT16 elements need 6 bytes, 4 are given.
    const auto a = oneColumn(*store, var, 1, {le<uint16_t>({1, 2}), le<uint32_t>({0, 3})});
    expectRefused(*store, a, {"'list'", "too short"});
}

TEST(PropertiesBad, OffsetsMissingOrTooFew) {
    auto store = make<PropertyStore>();
    ClassProperty var = prop("list", PropertyType::Scalar, ComponentType::UInt8);
    var.array = true;
    expectRefused(*store, oneColumn(*store, var, 1, {le<uint8_t>({1})}), {"'list'", "arrayOffsets"});
    // Two rows need three offsets.
    expectRefused(*store, oneColumn(*store, var, 2, {le<uint8_t>({1}), le<uint32_t>({0, 1})}),
                  {"'list'", "arrayOffsets too short"});
    expectRefused(*store, oneColumn(*store, prop("name", PropertyType::String), 1, {textBytes("a")}),
                  {"'name'", "stringOffsets"});
}

TEST(PropertiesBad, EnumValueNotInTheEnum) {
    auto store = make<PropertyStore>();
    store->schema.enums.push_back({"kind", "", ComponentType::UInt8, {{"House", 0}, {"Shed", 1}}});
    ClassProperty p = prop("kind", PropertyType::Enum);
    p.enumIndex = 0;
    const auto t = oneColumn(*store, p, 3, {le<uint8_t>({0, 5, 1})});
    expectRefused(*store, t, {"'kind'", "value 5", "not in enum 'kind'"});
}

TEST(PropertiesBad, UnknownPropertyOrClass) {
    auto store = make<PropertyStore>();
    auto t = oneColumn(*store, prop("height", PropertyType::Scalar, ComponentType::UInt8), 1, {le<uint8_t>({1})});
    t.columns[0].property = 3;
    expectRefused(*store, t, {"property 3", "no such property"});
    t.columns[0].property = 0;
    t.classIndex = 7;
    expectRefused(*store, t, {"no class 7"});
}

TEST(PropertiesBad, SpanPastItsBuffer) {
    auto store = make<PropertyStore>();
    auto t = oneColumn(*store, prop("height", PropertyType::Scalar, ComponentType::UInt8), 1, {le<uint8_t>({1})});
    t.columns[0].values.offset = 1;  // 1 byte from offset 1 of a 1-byte buffer
    expectRefused(*store, t, {"'height'", "past the buffer"});
    t.columns[0].values.offset = 0;
    t.columns[0].values.buffer = 9;
    expectRefused(*store, t, {"'height'", "no buffer 9"});
}

TEST(PropertiesBad, HugeCountsDoNotOverflow) {
    auto store = make<PropertyStore>();
    ClassProperty fixed = prop("pair", PropertyType::Scalar, ComponentType::UInt64);
    fixed.array = true;
    fixed.count = 4;
    expectRefused(*store, oneColumn(*store, fixed, UINT64_MAX / 2, {le<uint64_t>({1})}), {"'pair'"});
    expectRefused(*store, oneColumn(*store, prop("s", PropertyType::String), UINT64_MAX, {{}, {}, le<uint8_t>({0})}),
                  {"'s'"});
}

}  // namespace
