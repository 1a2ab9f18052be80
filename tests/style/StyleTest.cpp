// Style: show, color and pointSize from expressions and conditions, defines, binding with types, and a style
// evaluated for every row of a hand-made property table.
#include "sg/style/Style.h"
#include "sg/style/StyleTable.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <string>

using namespace sg;

namespace {

using Props = std::map<std::string, PropertyValue>;
using C4 = std::array<float, 4>;

StyleLook look(const Style& style, const Props& props) {
    const StyleLookup lookup = [&props](const std::string& name) -> const PropertyValue* {
        const auto it = props.find(name);
        return it == props.end() ? nullptr : &it->second;
    };
    return style.evaluate(lookup);
}

Props height(double h) { return {{"Height", PropertyValue::ofNumber(h)}}; }

StyleRule conditions(std::vector<std::pair<std::string, std::string>> list) {
    std::vector<std::pair<StyleExpression, StyleExpression>> out;
    for (const auto& [c, e] : list) out.emplace_back(StyleExpression(c), StyleExpression(e));
    return StyleRule(std::move(out));
}

StyleRule rule(const std::string& text) { return StyleRule(StyleExpression(text)); }

}  // namespace

TEST(Style, DefaultsShowEveryFeatureWhiteAtPointSizeOne) {
    const StyleLook l = look(Style(), height(1));
    EXPECT_TRUE(l.show);
    EXPECT_EQ(l.color, (C4{1, 1, 1, 1}));
    EXPECT_EQ(l.pointSize, 1.0f);
}

TEST(Style, ConditionsPickTheFirstThatHolds) {
    Style s;
    s.setColor(conditions({{"${Height} >= 100", "color('#0000FF')"},
                           {"${Height} >= 10", "color('#FF0000')"},
                           {"true", "color('#FFFFFF', 0.5)"}}));
    EXPECT_EQ(look(s, height(150)).color, (C4{0, 0, 1, 1}));  // the second holds too: the first wins
    EXPECT_EQ(look(s, height(50)).color, (C4{1, 0, 0, 1}));
    EXPECT_EQ(look(s, height(1)).color, (C4{1, 1, 1, 0.5f}));
}

TEST(Style, NoConditionHoldingGivesTheDefault) {
    Style s;
    s.setColor(conditions({{"${Height} >= 100", "color('red')"}}));
    EXPECT_EQ(look(s, height(5)).color, (C4{1, 1, 1, 1}));
}

TEST(Style, ShowFalseHidesAndColorsAreClampedToUnit) {
    Style s;
    s.setShow(rule("false"));
    EXPECT_FALSE(look(s, height(1)).show);
    s.setShow(rule("${Height} > 10"));
    s.setColor(rule("color('red') * 2"));
    EXPECT_FALSE(look(s, height(5)).show);
    EXPECT_TRUE(look(s, height(20)).show);
    EXPECT_EQ(look(s, height(20)).color, (C4{1, 0, 0, 1}));
}

TEST(Style, PointSize) {
    Style s;
    s.setPointSize(rule("${Height} * 0.5"));
    EXPECT_EQ(look(s, height(6)).pointSize, 3.0f);
}

TEST(Style, DefinesStandForTheirExpressions) {
    Style s;
    s.setDefine("NewHeight", StyleExpression("${Height} / 2"));
    s.setDefine("HeightColor", StyleExpression("rgb(${Height}, 0, 0)"));
    s.setShow(rule("${NewHeight} > 10"));
    s.setColor(rule("${HeightColor}"));
    EXPECT_TRUE(look(s, height(30)).show);  // 15 > 10
    EXPECT_FALSE(look(s, height(10)).show);
    const C4 c = look(s, height(51)).color;
    EXPECT_FLOAT_EQ(c[0], 0.2f);  // 51 / 255
    EXPECT_EQ(c[3], 1.0f);
    EXPECT_EQ(s.names(), (std::vector<std::string>{"Height"}));
}

TEST(Style, ADefineMayReadThePropertyOfItsOwnName) {
    // The spec's example: a feature of height 150 is red.
    Style s;
    s.setDefine("Height", StyleExpression("${Height} / 2.0"));
    s.setColor(conditions({{"${Height} >= 100.0", "color('#0000FF')"}, {"${Height} >= 1.0", "color('#FF0000')"}}));
    EXPECT_EQ(look(s, height(150)).color, (C4{1, 0, 0, 1}));
}

TEST(Style, WrongTypesAreErrors) {
    Style s;
    s.setColor(rule("1"));
    EXPECT_THROW(look(s, height(1)), StyleError);
    Style t;
    t.setShow(conditions({{"${Height}", "true"}}));  // a condition must be a Boolean
    EXPECT_THROW(look(t, height(1)), StyleError);
    Style u;
    u.setShow(rule("'yes'"));
    try {
        look(u, height(1));
        FAIL();
    } catch (const StyleError& e) {
        EXPECT_EQ(e.reason(), "show must be a Boolean, not String");
        EXPECT_EQ(e.expression(), "'yes'");
    }
}

namespace {

// Slots as a binder numbers them: Height 0, Name 1.
class Row final : public StyleFeature {
public:
    Row(double h, std::string name) : values_{PropertyValue::ofNumber(h), PropertyValue::ofString(std::move(name))} {}
    const PropertyValue* property(int slot) const override { return slot >= 0 && slot < 2 ? &values_[slot] : nullptr; }

private:
    PropertyValue values_[2];
};

StyleBinding typed(const std::string& name) {
    StyleBinding b;
    if (name == "Height") b = StyleBinding{0, StyleValue::Kind::Number, nullptr};
    if (name == "Name") b = StyleBinding{1, StyleValue::Kind::String, nullptr};
    return b;
}

}  // namespace

TEST(Style, BoundStylesReadSlots) {
    Style s;
    s.setDefine("Tall", StyleExpression("${Height} > 100"));
    s.setShow(rule("${Tall} && ${Name} =~ regExp('^B')"));
    s.bind(typed);
    EXPECT_TRUE(s.evaluate(Row(150, "Bank")).show);
    EXPECT_FALSE(s.evaluate(Row(150, "Assembly")).show);
    EXPECT_FALSE(s.evaluate(Row(50, "Bank")).show);
}

TEST(Style, BindingFindsAPropertyOfTheWrongKind) {
    StyleExpression e("${Height} > 5 && ${Name} < 5");
    try {
        e.bind(typed);
        FAIL();
    } catch (const StyleError& err) {
        EXPECT_EQ(err.position(), 17u);  // the reference to Name
        EXPECT_NE(err.reason().find("${Name} is a String"), std::string::npos) << err.reason();
    }
    EXPECT_THROW(StyleExpression("${Name} === 5").bind(typed), StyleError);
    EXPECT_THROW(StyleExpression("!${Height}").bind(typed), StyleError);
    EXPECT_NO_THROW(StyleExpression("${Name} === 'Bank' || ${Height} * 2 > 5").bind(typed));
}

namespace {

template <class T>
std::vector<uint8_t> bytesOf(const std::vector<T>& v) {
    std::vector<uint8_t> out(v.size() * sizeof(T));
    std::memcpy(out.data(), v.data(), out.size());
    return out;
}

// A class "building" of a FLOAT32 height and a STRING name, and a table of three rows:
// (5, "a"), (50, "bb"), (500, "c").
ref_ptr<PropertyStore> buildings() {
    ref_ptr<PropertyStore> store = make<PropertyStore>();
    ClassDef building;
    building.id = "building";
    ClassProperty h, name;
    h.id = "height";
    h.type = PropertyType::Scalar;
    h.componentType = ComponentType::Float32;
    name.id = "name";
    name.type = PropertyType::String;
    building.properties = {h, name};
    store->schema.classes.push_back(building);
    const int heights = store->addBuffer(bytesOf(std::vector<float>{5.0f, 50.0f, 500.0f}));
    const int names = store->addBuffer({'a', 'b', 'b', 'c'});
    const int offsets = store->addBuffer(bytesOf(std::vector<uint32_t>{0, 1, 3, 4}));
    PropertyTable t;
    t.name = "buildings";
    t.classIndex = 0;
    t.count = 3;
    PropertyColumn hc, nc;
    hc.property = 0;
    hc.values = ByteSpan{heights, 0, 12};
    nc.property = 1;
    nc.values = ByteSpan{names, 0, 4};
    nc.stringOffsets = ByteSpan{offsets, 0, 16};
    t.columns = {hc, nc};
    store->addTable(t);
    return store;
}

}  // namespace

TEST(StyleTable, OneRgbaPerRowHiddenAsTransparent) {
    const ref_ptr<PropertyStore> store = buildings();
    Style s;
    s.setShow(rule("${height} < 100"));
    s.setColor(conditions({{"${height} >= 10", "color('red')"}, {"true", "rgba(0, 0, 255, 0.5)"}}));
    const StyledTable t = styleTable(s, *store, 0);
    // Row 0: rgba(0, 0, 255, 0.5), alpha 127.5 rounded; row 1: red; row 2: hidden (500 >= 100).
    EXPECT_EQ(t.rgba, (std::vector<uint8_t>{0, 0, 255, 128, 255, 0, 0, 255, 0, 0, 0, 0}));
    EXPECT_TRUE(t.pointSizes.empty());
}

TEST(StyleTable, StringsPointSizesAndBindErrors) {
    const ref_ptr<PropertyStore> store = buildings();
    Style s;
    s.setShow(rule("${name} !== 'bb'"));
    s.setPointSize(rule("${height} / 5"));
    const StyledTable t = styleTable(s, *store, 0);
    EXPECT_EQ(t.rgba, (std::vector<uint8_t>{255, 255, 255, 255, 0, 0, 0, 0, 255, 255, 255, 255}));
    EXPECT_EQ(t.pointSizes, (std::vector<float>{1.0f, 1.0f, 100.0f}));  // the hidden row keeps 1
    Style bad;
    bad.setShow(rule("${name} > 3"));
    EXPECT_THROW(styleTable(bad, *store, 0), StyleError);
    EXPECT_THROW(styleTable(s, *store, 1), std::out_of_range);
}
