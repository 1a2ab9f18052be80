// The styling language's built-in functions (the spec's "Built-in functions", colours, vectors, conversions and
// regular expressions' methods).
#include "sg/style/internal/CssColors.h"
#include "sg/style/internal/StyleProgram.h"

#include <cmath>
#include <cstring>

namespace sg::style {

namespace {

using Kind = StyleValue::Kind;

constexpr FunctionInfo kFunctions[] = {
    {"color", Fn::Color, 0, 2},       {"rgb", Fn::Rgb, 3, 3},
    {"rgba", Fn::Rgba, 4, 4},         {"hsl", Fn::Hsl, 3, 3},
    {"hsla", Fn::Hsla, 4, 4},         {"vec2", Fn::Vec2, 1, 2},
    {"vec3", Fn::Vec3, 1, 3},         {"vec4", Fn::Vec4, 1, 4},
    {"regExp", Fn::RegExp, 0, 2},     {"isNaN", Fn::IsNaN, 1, 1},
    {"isFinite", Fn::IsFinite, 1, 1}, {"Number", Fn::Number, 1, 1},
    {"String", Fn::String, 1, 1},     {"Boolean", Fn::Boolean, 1, 1},
    {"abs", Fn::Abs, 1, 1},           {"sqrt", Fn::Sqrt, 1, 1},
    {"floor", Fn::Floor, 1, 1},       {"ceil", Fn::Ceil, 1, 1},
    {"round", Fn::Round, 1, 1},       {"sign", Fn::Sign, 1, 1},
    {"fract", Fn::Fract, 1, 1},       {"exp", Fn::Exp, 1, 1},
    {"log", Fn::Log, 1, 1},           {"exp2", Fn::Exp2, 1, 1},
    {"log2", Fn::Log2, 1, 1},         {"cos", Fn::Cos, 1, 1},
    {"sin", Fn::Sin, 1, 1},           {"tan", Fn::Tan, 1, 1},
    {"acos", Fn::Acos, 1, 1},         {"asin", Fn::Asin, 1, 1},
    {"atan", Fn::Atan, 1, 1},         {"radians", Fn::Radians, 1, 1},
    {"degrees", Fn::Degrees, 1, 1},   {"min", Fn::Min, 2, 2},
    {"max", Fn::Max, 2, 2},           {"pow", Fn::Pow, 2, 2},
    {"atan2", Fn::Atan2, 2, 2},       {"clamp", Fn::Clamp, 3, 3},
    {"mix", Fn::Mix, 3, 3},           {"length", Fn::Length, 1, 1},
    {"distance", Fn::Distance, 2, 2}, {"dot", Fn::Dot, 2, 2},
    {"cross", Fn::Cross, 2, 2},       {"normalize", Fn::Normalize, 1, 1},
};
constexpr FunctionInfo kMethods[] = {
    {"test", Fn::Test, 2, 2}, {"exec", Fn::Exec, 2, 2}, {"toString", Fn::ToString, 1, 1}};

const char* fnName(Fn fn) {
    for (const FunctionInfo& f : kFunctions)
        if (f.fn == fn) return f.name;
    for (const FunctionInfo& f : kMethods)
        if (f.fn == fn) return f.name;
    return "?";
}

double number(const Program& p, uint32_t pos, Fn fn, const StyleValue& v) {
    if (!v.isNumber()) p.fail(pos, std::string(fnName(fn)) + " takes numbers, not " + styleKindName(v.kind));
    return v.number();
}

using Component = double (*)(const double* x);

// f over numbers and vectors of one size, a number standing for every component.
StyleValue componentwise(const Program& p, uint32_t pos, Fn fn, const StyleValue* a, int n, Component f) {
    int size = 0;
    for (int i = 0; i < n; ++i) {
        if (!a[i].isNumber() && !a[i].isVector())
            p.fail(pos, std::string(fnName(fn)) + " takes numbers or vectors, not " + styleKindName(a[i].kind));
        if (a[i].isVector() && size && a[i].size() != size)
            p.fail(pos, std::string(fnName(fn)) + " takes vectors of one size");
        if (a[i].isVector()) size = a[i].size();
    }
    std::array<double, 4> out{};
    for (int c = 0; c < std::max(size, 1); ++c) {
        double x[3];
        for (int i = 0; i < n; ++i) x[i] = a[i].isNumber() ? a[i].v[0] : a[i].v[size_t(c)];
        out[size_t(c)] = f(x);
    }
    return size ? StyleValue::ofVec(size, out) : StyleValue::ofNumber(out[0]);
}

Component unaryFunction(Fn fn) {
    switch (fn) {
        case Fn::Abs: return [](const double* x) { return std::fabs(x[0]); };
        case Fn::Sqrt: return [](const double* x) { return std::sqrt(x[0]); };
        case Fn::Floor: return [](const double* x) { return std::floor(x[0]); };
        case Fn::Ceil: return [](const double* x) { return std::ceil(x[0]); };
        case Fn::Round: return [](const double* x) { return std::floor(x[0] + 0.5); };  // JavaScript's: halves up
        case Fn::Sign: return [](const double* x) { return x[0] > 0 ? 1.0 : x[0] < 0 ? -1.0 : x[0]; };
        case Fn::Fract: return [](const double* x) { return x[0] - std::floor(x[0]); };
        case Fn::Exp: return [](const double* x) { return std::exp(x[0]); };
        case Fn::Log: return [](const double* x) { return std::log(x[0]); };
        case Fn::Exp2: return [](const double* x) { return std::exp2(x[0]); };
        case Fn::Log2: return [](const double* x) { return std::log2(x[0]); };
        case Fn::Cos: return [](const double* x) { return std::cos(x[0]); };
        case Fn::Sin: return [](const double* x) { return std::sin(x[0]); };
        case Fn::Tan: return [](const double* x) { return std::tan(x[0]); };
        case Fn::Acos: return [](const double* x) { return std::acos(x[0]); };
        case Fn::Asin: return [](const double* x) { return std::asin(x[0]); };
        case Fn::Atan: return [](const double* x) { return std::atan(x[0]); };
        case Fn::Radians: return [](const double* x) { return x[0] * M_PI / 180.0; };
        case Fn::Degrees: return [](const double* x) { return x[0] * 180.0 / M_PI; };
        case Fn::Min: return [](const double* x) { return std::fmin(x[0], x[1]); };
        case Fn::Max: return [](const double* x) { return std::fmax(x[0], x[1]); };
        case Fn::Pow: return [](const double* x) { return std::pow(x[0], x[1]); };
        case Fn::Atan2: return [](const double* x) { return std::atan2(x[0], x[1]); };
        case Fn::Clamp: return [](const double* x) { return std::fmin(std::fmax(x[0], x[1]), x[2]); };
        case Fn::Mix: return [](const double* x) { return x[0] * (1.0 - x[2]) + x[1] * x[2]; };
        default: return nullptr;
    }
}

// CSS's HSL to RGB, hue, saturation and lightness in 0..1.
double hueToRgb(double m1, double m2, double h) {
    if (h < 0) h += 1;
    if (h > 1) h -= 1;
    if (h * 6 < 1) return m1 + (m2 - m1) * 6 * h;
    if (h * 2 < 1) return m2;
    if (h * 3 < 2) return m1 + (m2 - m1) * (2.0 / 3.0 - h) * 6;
    return m1;
}

StyleValue hsl(double h, double s, double l, double alpha) {
    h = h - std::floor(h);
    const double m2 = l <= 0.5 ? l * (1 + s) : l + s - l * s;
    const double m1 = 2 * l - m2;
    if (s == 0) return StyleValue::ofVec(4, {l, l, l, alpha});
    return StyleValue::ofVec(
        4, {hueToRgb(m1, m2, h + 1.0 / 3), hueToRgb(m1, m2, h), hueToRgb(m1, m2, h - 1.0 / 3), alpha});
}

StyleValue color(const Program& p, uint32_t pos, const StyleValue* a, int n) {
    if (n == 0) return StyleValue::ofVec(4, {1, 1, 1, 1});
    if (a[0].kind != Kind::String) p.fail(pos, std::string("color takes a string, not ") + styleKindName(a[0].kind));
    const auto c = parseCssColor(a[0].string);
    if (!c) p.fail(pos, "unknown color '" + a[0].string + "'");
    StyleValue v = StyleValue::ofVec(4, *c);
    if (n == 2) v.v[3] = number(p, pos, Fn::Color, a[1]);
    return v;
}

// GLSL's constructors: one number for every component, one longer vector cut, or parts adding up to `size`.
StyleValue vector(const Program& p, uint32_t pos, Fn fn, int size, const StyleValue* a, int n) {
    if (n == 1 && a[0].isNumber()) return StyleValue::ofVec(size, {a[0].v[0], a[0].v[0], a[0].v[0], a[0].v[0]});
    if (n == 1 && a[0].isVector() && a[0].size() >= size) return StyleValue::ofVec(size, a[0].v);
    std::array<double, 4> c{};
    int k = 0;
    for (int i = 0; i < n; ++i) {
        if (!a[i].isNumber() && !a[i].isVector())
            p.fail(pos, std::string(fnName(fn)) + " takes numbers and vectors, not " + styleKindName(a[i].kind));
        const int m = a[i].isNumber() ? 1 : a[i].size();
        for (int j = 0; j < m; ++j, ++k)
            if (k < 4) c[size_t(k)] = a[i].v[size_t(j)];
    }
    if (k != size)
        p.fail(pos,
               std::string(fnName(fn)) + " needs " + std::to_string(size) + " components, not " + std::to_string(k));
    return StyleValue::ofVec(size, c);
}

// length, distance, dot, cross, normalize: over whole vectors.
StyleValue geometric(const Program& p, uint32_t pos, Fn fn, const StyleValue* a, int n) {
    for (int i = 0; i < n; ++i)
        if ((!a[i].isNumber() && !a[i].isVector()) || a[i].kind != a[0].kind)
            p.fail(pos, std::string(fnName(fn)) + " takes numbers or vectors of one size");
    const int size = std::max(a[0].size(), 1);
    auto dot = [size](const std::array<double, 4>& x, const std::array<double, 4>& y) {
        double s = 0;
        for (size_t i = 0; i < size_t(size); ++i) s += x[i] * y[i];
        return s;
    };
    switch (fn) {
        case Fn::Length: return StyleValue::ofNumber(std::sqrt(dot(a[0].v, a[0].v)));
        case Fn::Dot: return StyleValue::ofNumber(dot(a[0].v, a[1].v));
        case Fn::Distance: {
            std::array<double, 4> d{};
            for (size_t i = 0; i < 4; ++i) d[i] = a[0].v[i] - a[1].v[i];
            return StyleValue::ofNumber(std::sqrt(dot(d, d)));
        }
        case Fn::Normalize: {
            if (a[0].isNumber()) return StyleValue::ofNumber(1.0);
            StyleValue v = a[0];
            const double len = std::sqrt(dot(v.v, v.v));
            for (double& c : v.v) c /= len;
            return StyleValue::ofVec(size, v.v);
        }
        default: break;
    }
    if (a[0].kind != Kind::Vec3) p.fail(pos, "cross takes two vec3");
    const auto& x = a[0].v;
    const auto& y = a[1].v;
    return StyleValue::ofVec(3, {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0], 0});
}

StyleValue regExpMethod(const Program& p, uint32_t pos, Fn fn, const StyleValue* a) {
    if (a[0].kind != Kind::RegExp) p.fail(pos, std::string(fnName(fn)) + " is a method of a regExp");
    const std::string s = a[1].toString();
    if (fn == Fn::Test) return StyleValue::ofBool(std::regex_search(s, a[0].regExp->regex));
    // exec: the first captured group (the whole match when the pattern has none); null when nothing matches.
    std::smatch m;
    if (!std::regex_search(s, m, a[0].regExp->regex)) return StyleValue::null();
    const size_t g = m.size() > 1 ? 1 : 0;
    return m[g].matched ? StyleValue::ofString(m[g].str()) : StyleValue::undefined();
}

}  // namespace

const FunctionInfo* findFunction(const std::string& name) {
    for (const FunctionInfo& f : kFunctions)
        if (name == f.name) return &f;
    return nullptr;
}

const FunctionInfo* findMethod(const std::string& name) {
    for (const FunctionInfo& f : kMethods)
        if (name == f.name) return &f;
    return nullptr;
}

std::shared_ptr<const StyleRegExp> compileRegExp(const Program& p, uint32_t pos, const std::string& pattern,
                                                 const std::string& flags) {
    auto syntax = std::regex::ECMAScript;
    for (char f : flags) {
        if (f == 'i')
            syntax |= std::regex::icase;
        else if (f == 'm')
            syntax |= std::regex::multiline;
        else if (!std::strchr("guy", f))
            p.fail(pos, std::string("unknown regExp flag '") + f + "'");
    }
    try {
        return std::make_shared<StyleRegExp>(StyleRegExp{std::regex(pattern, syntax), pattern, flags});
    } catch (const std::regex_error& e) {
        p.fail(pos, "bad regExp '" + pattern + "': " + e.what());
    }
}

StyleValue callFunction(const Program& p, uint32_t pos, Fn fn, StyleValue* a, int n) {
    if (const Component f = unaryFunction(fn)) return componentwise(p, pos, fn, a, n, f);
    switch (fn) {
        case Fn::Color: return color(p, pos, a, n);
        case Fn::Rgb:
        case Fn::Rgba: {
            double c[4] = {0, 0, 0, 255};
            for (int i = 0; i < n; ++i) c[i] = number(p, pos, fn, a[i]);
            return StyleValue::ofVec(4, {c[0] / 255, c[1] / 255, c[2] / 255, n == 4 ? c[3] : 1.0});
        }
        case Fn::Hsl:
        case Fn::Hsla: {
            double c[4] = {0, 0, 0, 1};
            for (int i = 0; i < n; ++i) c[i] = number(p, pos, fn, a[i]);
            return hsl(c[0], c[1], c[2], c[3]);
        }
        case Fn::Vec2: return vector(p, pos, fn, 2, a, n);
        case Fn::Vec3: return vector(p, pos, fn, 3, a, n);
        case Fn::Vec4: return vector(p, pos, fn, 4, a, n);
        case Fn::RegExp: {
            for (int i = 0; i < n; ++i)
                if (a[i].kind != Kind::String) p.fail(pos, "regExp takes strings");
            return StyleValue::ofRegExp(compileRegExp(p, pos, n ? a[0].string : "(?:)", n > 1 ? a[1].string : ""));
        }
        case Fn::IsNaN: return StyleValue::ofBool(std::isnan(a[0].toNumber()));
        case Fn::IsFinite: return StyleValue::ofBool(std::isfinite(a[0].toNumber()));
        case Fn::Number: return StyleValue::ofNumber(a[0].toNumber());
        case Fn::String:
        case Fn::ToString: return StyleValue::ofString(a[0].toString());
        case Fn::Boolean: return StyleValue::ofBool(a[0].truthy());
        case Fn::Test:
        case Fn::Exec: return regExpMethod(p, pos, fn, a);
        default: return geometric(p, pos, fn, a, n);
    }
}

}  // namespace sg::style
