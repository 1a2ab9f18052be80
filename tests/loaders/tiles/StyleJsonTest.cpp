// parseStyleJson: a 3D Tiles style's JSON into a Style, and its errors naming the JSON path.
#include "loaders/tiles/StyleJson.h"

#include <gtest/gtest.h>

#include <map>
#include <string>

using namespace sg;

namespace {

StyleLook look(const Style& style, double height) {
    const PropertyValue h = PropertyValue::ofNumber(height);
    const StyleLookup lookup = [&h](const std::string& name) { return name == "Height" ? &h : nullptr; };
    return style.evaluate(lookup);
}

// "path: reason" of the LoadError parsing `text` throws, or "" when it throws none.
std::string loadError(const std::string& text) {
    try {
        parseStyleJson("style.json", text);
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), "style.json");
        return e.jsonPath() + ": " + e.reason();
    }
    return "";
}

}  // namespace

TEST(StyleJson, TheSpecsExample) {
    const Style s = parseStyleJson("style.json", R"j({
        "defines": {"Half": "${Height} / 2"},
        "show": "${Half} > 0",
        "color": {"conditions": [
            ["${Height} < 60", "color('#13293D')"],
            ["${Height} < 120", "color('#1B98E0')"],
            ["true", "color('#E8F1F2', 0.5)"]
        ]},
        "pointSize": 3
    })j");
    EXPECT_FALSE(look(s, 0).show);
    const std::array<float, 4> c = look(s, 100).color;  // #1B98E0
    EXPECT_FLOAT_EQ(c[0], 0x1B / 255.0f);
    EXPECT_FLOAT_EQ(c[1], 0x98 / 255.0f);
    EXPECT_FLOAT_EQ(c[2], 0xE0 / 255.0f);
    EXPECT_EQ(c[3], 1.0f);
    EXPECT_EQ(look(s, 500).color[3], 0.5f);
    EXPECT_EQ(look(s, 500).pointSize, 3.0f);
}

TEST(StyleJson, ShowAsABoolean) {
    EXPECT_FALSE(look(parseStyleJson("s.json", R"j({"show": false})j"), 1).show);
    EXPECT_TRUE(look(parseStyleJson("s.json", R"j({"show": true})j"), 1).show);
}

TEST(StyleJson, MetaAndUnknownMembersAreWarnings) {
    std::vector<std::string> warnings;
    parseStyleJson("s.json", R"j({"meta": {"d": "'x'"}, "colour": "color('red')"})j", &warnings);
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_EQ(warnings[0], "colour: not a style member: left out");  // nlohmann keeps members sorted
    EXPECT_EQ(warnings[1], "meta: meta properties are not read: left out");
}

TEST(StyleJson, ErrorsNameTheJsonPath) {
    EXPECT_EQ(loadError("{"), ": not JSON");
    EXPECT_EQ(loadError("[]"), ": a style must be a JSON object");
    EXPECT_EQ(loadError(R"j({"show": "${Height} > > 50"})j"), "show: ${Height} > > 50: at 12: expected an expression");
    EXPECT_EQ(loadError(R"j({"color": {"conditions": [["true", "color('red')"], ["1 +", "color('red')"]]}})j"),
              "color.conditions[1][0]: 1 +: at 3: expected an expression");
    EXPECT_EQ(loadError(R"j({"color": {"conditions": [["true"]]}})j"),
              "color.conditions[0]: must be an array of [condition, expression]");
    EXPECT_EQ(loadError(R"j({"color": 5})j"), "color: must be an expression (a string), not number");
    EXPECT_EQ(loadError(R"j({"defines": {"a": "foo()"}})j"), "defines.a: foo(): at 0: unknown function 'foo'");
    EXPECT_EQ(loadError(R"j({"defines": []})j"), "defines: must be an object of name: expression");
}
