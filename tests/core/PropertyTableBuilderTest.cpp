#include "sg/core/PropertyTableBuilder.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

using V = PropertyValue;

// height FLOAT64, floors UINT16, name STRING, lit BOOLEAN, use ENUM: three rows.
PropertyTableBuilder threeRows() {
    PropertyTableBuilder b("building", "buildings");
    b.addScalar("height", ComponentType::Float64);
    b.addScalar("floors", ComponentType::UInt16);
    b.addString("name");
    b.addBoolean("lit");
    b.addEnum("use", "use", {"residential", "office", "retail", "industrial"});
    b.addRow({V::ofNumber(12.5), V::ofUInt(3), V::ofString("ab"), V::ofBool(true), V::ofString("office")});
    b.addRow({V::ofNumber(40.0), V::ofInt(11), V::ofString(""), V::ofBool(false), V::ofString("retail")});
    b.addRow({V::ofNumber(0.25), V::ofUInt(65535), V::ofString("xyz"), V::ofBool(true), V::ofString("residential")});
    return b;
}

}  // namespace

TEST(PropertyTableBuilder, WritesEachColumnInTheSpecsLayoutEightByteAligned) {
    const std::vector<uint8_t> bytes = threeRows().bytes();
    const std::vector<uint8_t> expected = {
        // height at 0: 12.5 = 0x4029000000000000, 40 = 0x4044000000000000, 0.25 = 0x3FD0000000000000
        0, 0, 0, 0, 0, 0, 0x29, 0x40, 0, 0, 0, 0, 0, 0, 0x44, 0x40, 0, 0, 0, 0, 0, 0, 0xD0, 0x3F,
        // floors at 24: 3, 11, 65535, then padding to 32
        3, 0, 11, 0, 0xFF, 0xFF, 0, 0,
        // name at 32: "ab" "" "xyz", padding to 40; stringOffsets at 40: 0, 2, 2, 5 (rows + 1)
        'a', 'b', 'x', 'y', 'z', 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 5, 0, 0, 0,
        // lit at 56: rows 0 and 2 set, least significant bit first; padding to 64
        0x05, 0, 0, 0, 0, 0, 0, 0,
        // use at 64: office 1, retail 2, residential 0 (UINT16)
        1, 0, 2, 0, 0, 0};
    EXPECT_EQ(bytes, expected);
}

TEST(PropertyTableBuilder, RefusesAValueThatDoesNotFitItsColumnAndKeepsTheRowsBefore) {
    PropertyTableBuilder b = threeRows();
    const auto row = [](V floors, V use) {
        return std::vector<V>{V::ofNumber(1), std::move(floors), V::ofString("n"), V::ofBool(false), std::move(use)};
    };
    EXPECT_THROW(b.addRow(row(V::ofUInt(65536), V::ofString("office"))), std::invalid_argument);
    EXPECT_THROW(b.addRow(row(V::ofInt(-1), V::ofString("office"))), std::invalid_argument);
    EXPECT_THROW(b.addRow(row(V::ofNumber(2.5), V::ofString("office"))), std::invalid_argument);
    EXPECT_THROW(b.addRow(row(V::ofString("3"), V::ofString("office"))), std::invalid_argument);
    EXPECT_THROW(b.addRow(row(V::ofUInt(3), V::ofString("farm"))), std::invalid_argument);
    EXPECT_THROW(b.addRow({V::ofNumber(1)}), std::invalid_argument);
    EXPECT_EQ(b.rows(), 3u);
    EXPECT_EQ(b.bytes(), threeRows().bytes());
    EXPECT_THROW(b.addString("late"), std::invalid_argument);
}

TEST(PropertyTableBuilder, FinishAddsTheClassTheEnumAndTheTableWithTheirSpans) {
    PropertyStore store;
    EXPECT_EQ(threeRows().finish(store), 0);
    ASSERT_EQ(store.schema.classes.size(), 1u);
    const ClassDef& cls = store.schema.classes[0];
    EXPECT_EQ(cls.id, "building");
    ASSERT_EQ(cls.properties.size(), 5u);
    EXPECT_EQ(cls.properties[1].componentType, ComponentType::UInt16);
    EXPECT_EQ(cls.properties[4].type, PropertyType::Enum);
    ASSERT_EQ(store.schema.enums.size(), 1u);
    EXPECT_EQ(cls.properties[4].enumIndex, 0);
    EXPECT_EQ(*store.schema.enums[0].nameOf(3), "industrial");
    ASSERT_EQ(store.tables().size(), 1u);
    const PropertyTable& t = store.tables()[0];
    EXPECT_EQ(t.name, "buildings");
    EXPECT_EQ(t.count, 3u);
    ASSERT_EQ(t.columns.size(), 5u);
    EXPECT_EQ(t.columns[1].values.offset, 24u);
    EXPECT_EQ(t.columns[2].values.offset, 32u);
    EXPECT_EQ(t.columns[2].values.size, 5u);
    EXPECT_EQ(t.columns[2].stringOffsets.offset, 40u);
    EXPECT_EQ(t.columns[2].stringOffsets.size, 16u);
    EXPECT_EQ(t.columns[4].values.offset, 64u);
    EXPECT_EQ(store.buffer(0).size(), 70u);
    // A second class of the same id is refused, and leaves the schema as it was.
    EXPECT_THROW(threeRows().finish(store), std::invalid_argument);
    EXPECT_EQ(store.schema.classes.size(), 1u);
    EXPECT_EQ(store.tables().size(), 1u);
}

TEST(PropertyTableBuilder, TheStoreReadsBackWhatWasPut) {
    PropertyStore store;
    const int t = threeRows().finish(store);
    EXPECT_DOUBLE_EQ(store.value(t, 0, 0).asNumber(), 12.5);
    EXPECT_DOUBLE_EQ(store.value(t, 2, 0).asNumber(), 0.25);
    EXPECT_DOUBLE_EQ(store.value(t, 2, 1).asNumber(), 65535.0);
    EXPECT_EQ(store.value(t, 0, 2).string, "ab");
    EXPECT_EQ(store.value(t, 1, 2).string, "");
    EXPECT_EQ(store.value(t, 2, 2).string, "xyz");
    EXPECT_TRUE(store.value(t, 0, 3).boolean);
    EXPECT_FALSE(store.value(t, 1, 3).boolean);
    EXPECT_TRUE(store.value(t, 2, 3).boolean);
    EXPECT_EQ(store.value(t, 0, 4).string, "office");
    EXPECT_EQ(store.value(t, 1, 4).string, "retail");
    EXPECT_EQ(store.value(t, 2, 4).string, "residential");
    EXPECT_TRUE(store.value(t, 3, 0).isNull());  // past the table
}

TEST(PropertyTableBuilder, RowFeaturesNameEachRowByItsIndex) {
    auto store = make<PropertyStore>();
    const int t = threeRows().finish(*store);
    const ref_ptr<MeshFeatures> f = rowFeatures(store, t, "buildings");
    ASSERT_EQ(f->sets.size(), 1u);
    EXPECT_EQ(f->sets[0].source, FeatureIdSet::Source::Instance);
    EXPECT_EQ(f->sets[0].featureCount, 3u);
    EXPECT_EQ(f->sets[0].propertyTable, t);
    EXPECT_EQ(f->sets[0].ids, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(f->store.get(), store.get());
    EXPECT_THROW(rowFeatures(store, 1), std::invalid_argument);
}
