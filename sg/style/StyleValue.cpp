#include "sg/style/StyleValue.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace sg {

StyleError::StyleError(std::string expression, size_t position, std::string reason)
    : std::runtime_error(expression + ": at " + std::to_string(position) + ": " + reason),
      expression_(std::move(expression)),
      position_(position),
      reason_(std::move(reason)) {}

StyleValue StyleValue::make(Kind k) {
    StyleValue v;
    v.kind = k;
    return v;
}

StyleValue StyleValue::ofBool(bool b) {
    StyleValue v = make(Kind::Boolean);
    v.boolean = b;
    return v;
}

StyleValue StyleValue::ofNumber(double d) {
    StyleValue v = make(Kind::Number);
    v.v[0] = d;
    return v;
}

StyleValue StyleValue::ofString(std::string s) {
    StyleValue v = make(Kind::String);
    v.string = std::move(s);
    return v;
}

StyleValue StyleValue::ofVec(int n, std::array<double, 4> c) {
    StyleValue v = make(n == 2 ? Kind::Vec2 : n == 3 ? Kind::Vec3 : Kind::Vec4);
    for (int i = n; i < 4; ++i) c[size_t(i)] = 0.0;  // unused components stay 0 so that equality can read all four
    v.v = c;
    return v;
}

StyleValue StyleValue::ofRegExp(std::shared_ptr<const StyleRegExp> r) {
    StyleValue v = make(Kind::RegExp);
    v.regExp = std::move(r);
    return v;
}

StyleValue StyleValue::fromProperty(const PropertyValue* p) {
    if (!p) return undefined();
    using K = PropertyValue::Kind;
    switch (p->kind) {
        case K::Null: return null();
        case K::Boolean: return ofBool(p->boolean);
        case K::Integer: return ofNumber(double(p->integer));
        case K::Unsigned: return ofNumber(double(p->unsignedInteger));
        case K::Number: return ofNumber(p->number);
        case K::String: return ofString(p->string);
        case K::Array: {
            const size_t n = p->items.size();
            if (n < 2 || n > 4) return undefined();
            std::array<double, 4> c{};
            for (size_t i = 0; i < n; ++i) {
                const K k = p->items[i].kind;
                if (k != K::Integer && k != K::Unsigned && k != K::Number) return undefined();
                c[i] = p->items[i].asNumber();
            }
            return ofVec(int(n), c);
        }
    }
    return undefined();
}

int StyleValue::size() const {
    switch (kind) {
        case Kind::Vec2: return 2;
        case Kind::Vec3: return 3;
        case Kind::Vec4: return 4;
        default: return 0;
    }
}

namespace {

// JavaScript's Number(string): blanks trimmed, "" is 0, decimal or Infinity; anything else NaN.
double numberOfString(const std::string& s) {
    const size_t b = s.find_first_not_of(" \t\n\r\f\v");
    if (b == std::string::npos) return 0.0;
    const std::string t = s.substr(b, s.find_last_not_of(" \t\n\r\f\v") - b + 1);
    const double inf = std::numeric_limits<double>::infinity();
    if (t == "Infinity" || t == "+Infinity") return inf;
    if (t == "-Infinity") return -inf;
    // strtod also reads "inf", "nan" and hexadecimal floats, which JavaScript does not.
    if (t.find_first_not_of("0123456789.eE+-") != std::string::npos) return std::nan("");
    char* end = nullptr;
    const double d = std::strtod(t.c_str(), &end);
    return end == t.c_str() + t.size() ? d : std::nan("");
}

}  // namespace

double StyleValue::toNumber() const {
    switch (kind) {
        case Kind::Null: return 0.0;
        case Kind::Boolean: return boolean ? 1.0 : 0.0;
        case Kind::Number: return v[0];
        case Kind::String: return numberOfString(string);
        default: return std::nan("");
    }
}

bool StyleValue::truthy() const {
    switch (kind) {
        case Kind::Undefined:
        case Kind::Null: return false;
        case Kind::Boolean: return boolean;
        case Kind::Number: return v[0] != 0.0 && !std::isnan(v[0]);
        case Kind::String: return !string.empty();
        default: return true;
    }
}

std::string StyleValue::toString() const {
    switch (kind) {
        case Kind::Undefined: return "undefined";
        case Kind::Null: return "null";
        case Kind::Boolean: return boolean ? "true" : "false";
        case Kind::Number: return styleNumberString(v[0]);
        case Kind::String: return string;
        case Kind::RegExp: return "/" + regExp->pattern + "/" + regExp->flags;
        default: break;
    }
    std::string s = "(";
    for (int i = 0; i < size(); ++i) s += (i ? ", " : "") + styleNumberString(v[size_t(i)]);
    return s + ")";
}

bool StyleValue::strictEquals(const StyleValue& o) const {
    if (kind != o.kind) return false;
    switch (kind) {
        case Kind::Undefined:
        case Kind::Null: return true;
        case Kind::Boolean: return boolean == o.boolean;
        case Kind::Number: return v[0] == o.v[0];
        case Kind::String: return string == o.string;
        case Kind::RegExp: return regExp == o.regExp;
        default: return v == o.v;  // vectors: unused components are 0 in both
    }
}

std::string styleNumberString(double d) {
    if (std::isnan(d)) return "NaN";
    if (std::isinf(d)) return d > 0 ? "Infinity" : "-Infinity";
    if (d == std::floor(d) && std::fabs(d) < 1e21) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.0f", d == 0.0 ? 0.0 : d);  // -0 prints as "0", as in JavaScript
        return buf;
    }
    // The shortest text that reads back as the same double, as JavaScript prints.
    char buf[40];
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, d);
        if (std::strtod(buf, nullptr) == d) break;
    }
    std::string s = buf;
    const size_t e = s.find('e');
    if (e == std::string::npos) return s;
    // C writes "1e-07"; JavaScript "1e-7" and "1e+21".
    std::string mantissa = s.substr(0, e), sign = s.substr(e + 1, 1), digits = s.substr(e + 2);
    digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size() - 1));
    return mantissa + "e" + sign + digits;
}

const char* styleKindName(StyleValue::Kind k) {
    using K = StyleValue::Kind;
    switch (k) {
        case K::Undefined: return "undefined";
        case K::Null: return "null";
        case K::Boolean: return "Boolean";
        case K::Number: return "Number";
        case K::String: return "String";
        case K::Vec2: return "vec2";
        case K::Vec3: return "vec3";
        case K::Vec4: return "vec4";
        case K::RegExp: return "RegExp";
    }
    return "?";
}

}  // namespace sg
