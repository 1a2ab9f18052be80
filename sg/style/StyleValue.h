// A value of the 3D Tiles styling language as an expression computes it (a number, a colour, a string...), and
// StyleError, the one error the language reports, naming the expression, the position and the reason.
#pragma once
#include "sg/core/Properties.h"

#include <array>
#include <cstddef>
#include <memory>
#include <regex>
#include <stdexcept>
#include <string>

namespace sg {

// An expression that cannot be parsed, bound or evaluated: "${height} > > 50: at 12: expected an expression".
// position is the 0-based character of the expression text where the problem is.
class StyleError : public std::runtime_error {
public:
    StyleError(std::string expression, size_t position, std::string reason);
    const std::string& expression() const { return expression_; }
    size_t position() const { return position_; }
    const std::string& reason() const { return reason_; }

private:
    std::string expression_;
    size_t position_;
    std::string reason_;
};

// A compiled regExp(pattern, flags): its text kept for toString() and equality.
struct StyleRegExp {
    std::regex regex;
    std::string pattern, flags;
};

// The language's types (the spec's "Types"): a colour is a Vec4 of components 0..1. Arrays other than vectors
// are not values of the language here.
struct StyleValue {
    enum class Kind : uint8_t { Undefined, Null, Boolean, Number, String, Vec2, Vec3, Vec4, RegExp };
    Kind kind = Kind::Undefined;
    bool boolean = false;
    std::array<double, 4> v{};  // a Number in v[0]; a vector's components
    std::string string;
    std::shared_ptr<const StyleRegExp> regExp;

    static StyleValue undefined() { return {}; }
    static StyleValue null() { return make(Kind::Null); }
    static StyleValue ofBool(bool b);
    static StyleValue ofNumber(double d);
    static StyleValue ofString(std::string s);
    static StyleValue ofVec(int n, std::array<double, 4> c);  // n of 2..4
    static StyleValue ofRegExp(std::shared_ptr<const StyleRegExp> r);
    static StyleValue make(Kind k);
    // A property's value: numbers (integers included) as Number, strings and enum names as String, an array of
    // 2..4 numbers (a VECn) as a vector, Null as Null; other arrays as Undefined. nullptr (no such property):
    // Undefined.
    static StyleValue fromProperty(const PropertyValue* p);

    bool isNumber() const { return kind == Kind::Number; }
    bool isVector() const { return kind == Kind::Vec2 || kind == Kind::Vec3 || kind == Kind::Vec4; }
    int size() const;  // a vector's component count; 0 for the others
    double number() const { return v[0]; }
    // JavaScript's conversions (the spec's "Type conversions"): Number(), Boolean(), String().
    double toNumber() const;
    bool truthy() const;
    std::string toString() const;
    // The spec's ===: the same type and equal (NaN equal to nothing; regular expressions by identity).
    bool strictEquals(const StyleValue& o) const;
};

// A number as JavaScript prints it: "5", "0.5", "NaN", "Infinity", "-1e+21".
std::string styleNumberString(double d);
// A kind's name for messages: "Number", "vec3", "RegExp".
const char* styleKindName(StyleValue::Kind k);

}  // namespace sg
