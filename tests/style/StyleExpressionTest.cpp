// StyleExpression: the 3D Tiles styling language's operators, types, functions and colours, evaluated for a
// hand-made feature, and its errors with their positions.
#include "sg/style/StyleExpression.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

using namespace sg;
using Kind = StyleValue::Kind;

namespace {

const std::map<std::string, PropertyValue>& feature() {
    static const std::map<std::string, PropertyValue> f = {
        {"height", PropertyValue::ofNumber(50.0)},
        {"count", PropertyValue::ofInt(6)},
        {"name", PropertyValue::ofString("Main hall")},
        {"County", PropertyValue::ofString("Chester")},
        {"flag", PropertyValue::ofBool(true)},
        {"a b", PropertyValue::ofNumber(2.0)},
        {"feature", PropertyValue::ofString("building")},
        {"position",
         PropertyValue::ofArray({PropertyValue::ofNumber(1), PropertyValue::ofNumber(2), PropertyValue::ofNumber(3)})},
        {"nothing", PropertyValue{}},
    };
    return f;
}

StyleValue eval(const std::string& text) {
    const StyleLookup lookup = [](const std::string& name) -> const PropertyValue* {
        const auto it = feature().find(name);
        return it == feature().end() ? nullptr : &it->second;
    };
    return StyleExpression(text).evaluate(lookup);
}

double num(const std::string& text) {
    const StyleValue v = eval(text);
    EXPECT_EQ(v.kind, Kind::Number) << text;
    return v.number();
}

bool boolean(const std::string& text) {
    const StyleValue v = eval(text);
    EXPECT_EQ(v.kind, Kind::Boolean) << text;
    return v.boolean;
}

std::string str(const std::string& text) {
    const StyleValue v = eval(text);
    EXPECT_EQ(v.kind, Kind::String) << text;
    return v.string;
}

std::array<double, 4> vec(const std::string& text, Kind kind = Kind::Vec4) {
    const StyleValue v = eval(text);
    EXPECT_EQ(v.kind, kind) << text;
    return v.v;
}

// The StyleError of parsing and evaluating `text`: "at <position>: <reason>", or "" when there is none.
std::string error(const std::string& text) {
    try {
        eval(text);
    } catch (const StyleError& e) {
        EXPECT_EQ(e.expression(), text);
        return "at " + std::to_string(e.position()) + ": " + e.reason();
    }
    return "";
}

using V4 = std::array<double, 4>;

}  // namespace

TEST(StyleExpression, Arithmetic) {
    EXPECT_EQ(num("1 + 2 * 3"), 7);
    EXPECT_EQ(num("(1 + 2) * 3"), 9);
    EXPECT_EQ(num("2 - 3 - 4"), -5);  // left to right
    EXPECT_EQ(num("8 / 2 / 2"), 2);
    EXPECT_EQ(num("10 % 4"), 2);
    EXPECT_EQ(num("-7 % 3"), -1);  // the dividend's sign, as in JavaScript
    EXPECT_EQ(num("-2 * -3"), 6);
    EXPECT_EQ(num("+5"), 5);
    EXPECT_EQ(num("1.5e2 + .5"), 150.5);
    EXPECT_EQ(num("${height} * 2 + ${count}"), 106);
    EXPECT_TRUE(std::isinf(num("1 / 0")));
}

TEST(StyleExpression, Precedence) {
    EXPECT_TRUE(boolean("1 + 2 > 2 && 3 < 4"));
    EXPECT_TRUE(boolean("true || false && false"));
    EXPECT_TRUE(boolean("1 + 2 === 3"));
    EXPECT_EQ(num("2 * 3 + 4 * 5"), 26);
    EXPECT_EQ(num("false ? 1 : true ? 2 : 3"), 2);
    EXPECT_FALSE(boolean("!true === true"));  // (!true) === true
    EXPECT_EQ(num("-(2 + 3)"), -5);
}

TEST(StyleExpression, Comparisons) {
    EXPECT_TRUE(boolean("${height} >= 50"));
    EXPECT_FALSE(boolean("${height} > 50"));
    EXPECT_TRUE(boolean("${height} <= 50.0"));
    EXPECT_FALSE(boolean("${height} < 50"));
    EXPECT_TRUE(boolean("${name} === 'Main hall'"));
    EXPECT_FALSE(boolean("1 === '1'"));  // types differ: not equal, no conversion
    EXPECT_TRUE(boolean("1 !== '1'"));
    EXPECT_TRUE(boolean("null === null"));
    EXPECT_TRUE(boolean("${nothing} === null"));
    EXPECT_TRUE(boolean("${missing} === undefined"));
    EXPECT_FALSE(boolean("NaN === NaN"));
    EXPECT_TRUE(boolean("${count} === 6"));  // an integer property is a Number
}

TEST(StyleExpression, ShortCircuitLeavesTheOtherSideUnevaluated) {
    // ${name} * 2 would throw: a String times a Number.
    EXPECT_FALSE(boolean("false && ${name} * 2"));
    EXPECT_TRUE(boolean("true || ${name} * 2"));
    EXPECT_EQ(num("false ? ${name} * 2 : 1"), 1);
    EXPECT_NE(error("true && ${name} * 2"), "");
}

TEST(StyleExpression, Strings) {
    EXPECT_EQ(str("'a' + 1"), "a1");
    EXPECT_EQ(str("\"x\" + true"), "xtrue");
    EXPECT_EQ(str("'v' + vec2(1, 2.5)"), "v(1, 2.5)");
    EXPECT_EQ(str("'it\\'s'"), "it's");
    EXPECT_EQ(str("String(0.5)"), "0.5");
    EXPECT_EQ(str("String(1e21)"), "1e+21");
    EXPECT_EQ(str("String(0.1 + 0.2)"), "0.30000000000000004");
    EXPECT_EQ(str("String(null) + String(undefined)"), "nullundefined");
    EXPECT_EQ(str("${name} + '!'"), "Main hall!");
    EXPECT_EQ(num("Number('12') + 1"), 13);
    EXPECT_TRUE(std::isnan(num("Number('12px')")));
    EXPECT_EQ(num("Number(true)"), 1);
    EXPECT_FALSE(boolean("Boolean('')"));
    EXPECT_TRUE(boolean("Boolean(${name})"));
}

TEST(StyleExpression, References) {
    EXPECT_EQ(num("${feature['a b']}"), 2);
    EXPECT_EQ(num("${feature[\"a b\"]} + 1"), 3);
    EXPECT_EQ(str("${feature}"), "building");
    EXPECT_EQ(num("${feature.height}"), 50);
    EXPECT_EQ(eval("${missing}").kind, Kind::Undefined);
    EXPECT_EQ(eval("${nothing}").kind, Kind::Null);
    EXPECT_EQ(StyleExpression("${b} + ${a} * ${b}").names(), (std::vector<std::string>{"b", "a"}));
}

TEST(StyleExpression, RegExp) {
    EXPECT_TRUE(boolean("regExp('^Chest').test(${County})"));
    EXPECT_TRUE(boolean("${County} =~ regExp('ter$')"));
    EXPECT_TRUE(boolean("regExp('a') =~ 'abc'"));
    EXPECT_TRUE(boolean("regExp('a') !~ 'bcd'"));
    EXPECT_TRUE(boolean("'bcd' !~ regExp('a')"));
    EXPECT_FALSE(boolean("regExp('^chest') =~ ${County}"));
    EXPECT_TRUE(boolean("regExp('^chest', 'i') =~ ${County}"));
    EXPECT_EQ(str("regExp('a(.)', 'i').exec('Abc')"), "b");
    EXPECT_EQ(eval("regExp('x').exec('abc')").kind, Kind::Null);
    EXPECT_EQ(str("String(regExp('a'))"), "/a/");
    EXPECT_TRUE(boolean("regExp() =~ 'anything'"));
    EXPECT_EQ(error("regExp('(')").substr(0, 20), "at 0: bad regExp '('");
    EXPECT_EQ(error("regExp('a', 'q')"), "at 0: unknown regExp flag 'q'");
    EXPECT_EQ(error("regExp('a') =~ 5"), "at 12: operator '=~' takes a string and a regExp, not RegExp and Number");
}

TEST(StyleExpression, ColorFunctions) {
    EXPECT_EQ(vec("color('red')"), (V4{1, 0, 0, 1}));
    EXPECT_EQ(vec("color('Green')"), (V4{0, 128 / 255.0, 0, 1}));  // CSS green; case-insensitive
    EXPECT_EQ(vec("color('cornflowerblue')"), (V4{100 / 255.0, 149 / 255.0, 237 / 255.0, 1}));
    EXPECT_EQ(vec("color('#00FFFF')"), (V4{0, 1, 1, 1}));
    EXPECT_EQ(vec("color('#0F8')"), (V4{0, 1, 136 / 255.0, 1}));
    EXPECT_EQ(vec("color('cyan', 0.5)"), (V4{0, 1, 1, 0.5}));
    EXPECT_EQ(vec("color()"), (V4{1, 1, 1, 1}));
    EXPECT_EQ(vec("color('transparent')"), (V4{0, 0, 0, 0}));
    EXPECT_EQ(vec("rgb(255, 0, 51)"), (V4{1, 0, 51 / 255.0, 1}));
    EXPECT_EQ(vec("rgba(0, 255, 0, 0.25)"), (V4{0, 1, 0, 0.25}));
    EXPECT_EQ(vec("hsl(0, 0, 0.25)"), (V4{0.25, 0.25, 0.25, 1}));  // no saturation: grey of that lightness
    const V4 red = vec("hsl(0, 1, 0.5)");
    const V4 cyan = vec("hsla(0.5, 1, 0.5, 0.75)");
    const V4 wantRed{1, 0, 0, 1}, wantCyan{0, 1, 1, 0.75};
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(red[i], wantRed[i], 1e-12) << i;
        EXPECT_NEAR(cyan[i], wantCyan[i], 1e-12) << i;
    }
    EXPECT_EQ(vec("color('red') * vec4(0.5)"), (V4{0.5, 0, 0, 0.5}));
    EXPECT_EQ(num("color('red').r + color('red')[3]"), 2);
    EXPECT_TRUE(boolean("color('red') === vec4(1, 0, 0, 1)"));  // a colour is a vec4
    EXPECT_EQ(str("color('red').toString()"), "(1, 0, 0, 1)");
    EXPECT_EQ(error("color('nocolor')"), "at 0: unknown color 'nocolor'");
    EXPECT_EQ(error("color('#12345')"), "at 0: unknown color '#12345'");
}

TEST(StyleExpression, Vectors) {
    EXPECT_EQ(vec("vec3(1, vec2(2, 3))", Kind::Vec3), (V4{1, 2, 3, 0}));
    EXPECT_EQ(num("vec4(vec3(1, 2, 3), 4).z"), 3);
    EXPECT_EQ(vec("vec2(vec4(1, 2, 3, 4))", Kind::Vec2), (V4{1, 2, 0, 0}));
    EXPECT_EQ(vec("vec3(1) + vec3(1, 2, 3)", Kind::Vec3), (V4{2, 3, 4, 0}));
    EXPECT_EQ(vec("vec2(1, 2) * 3", Kind::Vec2), (V4{3, 6, 0, 0}));
    EXPECT_EQ(vec("-vec2(1, 2)", Kind::Vec2), (V4{-1, -2, 0, 0}));
    EXPECT_TRUE(boolean("vec2(1, 2) === vec2(1, 2)"));
    EXPECT_FALSE(boolean("vec3(1) === vec4(1)"));
    EXPECT_EQ(num("${position}.y"), 2);  // a numeric array of 3 is a vec3
    EXPECT_EQ(num("length(vec2(3, 4))"), 5);
    EXPECT_EQ(num("dot(vec3(1, 2, 3), vec3(4, 5, 6))"), 32);
    EXPECT_EQ(vec("cross(vec3(1, 0, 0), vec3(0, 1, 0))", Kind::Vec3), (V4{0, 0, 1, 0}));
    EXPECT_EQ(error("vec4(vec3(1, 2, 3))"), "at 0: vec4 needs 4 components, not 3");
    EXPECT_EQ(error("vec2(1) + vec3(1)"),
              "at 8: operator '+' takes numbers, vectors of one size or a string, not vec2 and vec3");
}

TEST(StyleExpression, MathFunctions) {
    EXPECT_EQ(num("abs(-2)"), 2);
    EXPECT_EQ(num("min(3, 1) + max(3, 1)"), 4);
    EXPECT_EQ(num("clamp(5, 0, 2)"), 2);
    EXPECT_EQ(num("floor(1.7) + ceil(1.2)"), 3);
    EXPECT_EQ(num("round(2.5)"), 3);
    EXPECT_EQ(num("sqrt(16)"), 4);
    EXPECT_EQ(num("pow(2, 10)"), 1024);
    EXPECT_EQ(num("mix(0, 10, 0.25)"), 2.5);
    EXPECT_EQ(num("Math.PI"), M_PI);
    EXPECT_TRUE(boolean("isNaN(NaN) && isNaN('abc') && !isNaN(1)"));
    EXPECT_FALSE(boolean("isFinite(1 / 0)"));
    EXPECT_EQ(vec("abs(vec2(-1, 2))", Kind::Vec2), (V4{1, 2, 0, 0}));
    EXPECT_EQ(vec("clamp(vec2(-1, 2), 0, 1)", Kind::Vec2), (V4{0, 1, 0, 0}));
    EXPECT_EQ(error("abs('a')"), "at 0: abs takes numbers or vectors, not String");
}

TEST(StyleExpression, SyntaxErrorsNameTheirPosition) {
    EXPECT_EQ(error("${height} > > 50"), "at 12: expected an expression");
    EXPECT_EQ(error("1 +"), "at 3: expected an expression");
    EXPECT_EQ(error(""), "at 0: expected an expression");
    EXPECT_EQ(error("(1 + 2"), "at 6: expected ')'");
    EXPECT_EQ(error("1 2"), "at 2: unexpected '2'");
    EXPECT_EQ(error("foo(1)"), "at 0: unknown function 'foo'");
    EXPECT_EQ(error("1 + height"), "at 4: unknown name 'height' (a property is ${height})");
    EXPECT_EQ(error("'abc"), "at 0: unterminated string");
    EXPECT_EQ(error("2 * ${height"), "at 4: unterminated ${");
    EXPECT_EQ(error("1 == 1"), "at 2: '==' is not supported: use '==='");
    EXPECT_EQ(error("color('red', 1, 2)"), "at 0: color takes 0 to 2 arguments, not 3");
    EXPECT_EQ(error("1 # 2"), "at 2: unexpected character '#'");
    EXPECT_EQ(error("[1, 2]"), "at 0: array literals are not supported");
    EXPECT_EQ(error(std::string(300, '(') + "1" + std::string(300, ')')).find("nested too deeply") != std::string::npos,
              true);
    try {
        StyleExpression("${height} > > 50");
        FAIL();
    } catch (const StyleError& e) {
        EXPECT_STREQ(e.what(), "${height} > > 50: at 12: expected an expression");
    }
}

TEST(StyleExpression, TypeErrorsNameTheirOperator) {
    // Constants are computed when parsed: their errors come then.
    EXPECT_EQ(error("'abc' * 2"), "at 6: operator '*' takes numbers or vectors of one size, not String and Number");
    EXPECT_EQ(error("1 ? 2 : 3"), "at 2: the condition of '?:' must be a Boolean, not Number");
    EXPECT_EQ(error("!1"), "at 0: operator '!' takes a Boolean, not Number");
    // A property's, when evaluated.
    EXPECT_EQ(error("${name} * 2"), "at 8: operator '*' takes numbers or vectors of one size, not String and Number");
    EXPECT_EQ(error("${missing} > 5"), "at 11: operator '>' takes numbers, not undefined and Number");
    EXPECT_EQ(error("${height} && true"), "at 10: the left side of a logical operator must be a Boolean, not Number");
}
