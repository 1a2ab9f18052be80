// The evaluator: one recursive walk of the tree per feature, operands checked as the spec's "Operator rules" say
// (no implicit conversions but + with a string).
#include "sg/style/internal/StyleProgram.h"

#include <cmath>

namespace sg::style {

namespace {

using Kind = StyleValue::Kind;

const char* opText(Op op) {
    switch (op) {
        case Op::Neg:
        case Op::Sub: return "-";
        case Op::Plus:
        case Op::Add: return "+";
        case Op::Not: return "!";
        case Op::Mul: return "*";
        case Op::Div: return "/";
        case Op::Mod: return "%";
        case Op::Lt: return "<";
        case Op::Le: return "<=";
        case Op::Gt: return ">";
        case Op::Ge: return ">=";
        case Op::And: return "&&";
        case Op::Or: return "||";
        case Op::Match: return "=~";
        case Op::NoMatch: return "!~";
        default: return "?";
    }
}

[[noreturn]] void badOperands(const Program& p, const Node& n, const StyleValue& l, const StyleValue* r,
                              const char* wanted) {
    std::string got = styleKindName(l.kind);
    if (r) got += std::string(" and ") + styleKindName(r->kind);
    p.fail(n.pos, std::string("operator '") + opText(n.op) + "' takes " + wanted + ", not " + got);
}

double apply(Op op, double x, double y) {
    switch (op) {
        case Op::Add: return x + y;
        case Op::Sub: return x - y;
        case Op::Mul: return x * y;
        case Op::Div: return x / y;
        default: return std::fmod(x, y);  // JavaScript's %: the sign of the dividend
    }
}

// + - * / % over numbers and vectors; + joins strings.
StyleValue arithmetic(const Program& p, const Node& n, const StyleValue& l, const StyleValue& r) {
    if (n.op == Op::Add && (l.kind == Kind::String || r.kind == Kind::String))
        return StyleValue::ofString(l.toString() + r.toString());
    if (l.isNumber() && r.isNumber()) return StyleValue::ofNumber(apply(n.op, l.number(), r.number()));
    const bool scaleRight = r.isNumber() && l.isVector() && (n.op == Op::Mul || n.op == Op::Div);
    const bool scaleLeft = l.isNumber() && r.isVector() && n.op == Op::Mul;
    if (!(l.isVector() && l.kind == r.kind) && !scaleRight && !scaleLeft)
        badOperands(p, n, l, &r,
                    n.op == Op::Add ? "numbers, vectors of one size or a string" : "numbers or vectors of one size");
    const int size = l.isVector() ? l.size() : r.size();
    std::array<double, 4> c{};
    for (size_t i = 0; i < size_t(size); ++i)
        c[i] = apply(n.op, scaleLeft ? l.v[0] : l.v[i], scaleRight ? r.v[0] : r.v[i]);
    return StyleValue::ofVec(size, c);
}

StyleValue compare(const Program& p, const Node& n, const StyleValue& l, const StyleValue& r) {
    if (!l.isNumber() || !r.isNumber()) badOperands(p, n, l, &r, "numbers");
    const double x = l.number(), y = r.number();
    switch (n.op) {
        case Op::Lt: return StyleValue::ofBool(x < y);
        case Op::Le: return StyleValue::ofBool(x <= y);
        case Op::Gt: return StyleValue::ofBool(x > y);
        default: return StyleValue::ofBool(x >= y);
    }
}

// =~ and !~: a string and a regular expression, either way round.
StyleValue match(const Program& p, const Node& n, const StyleValue& l, const StyleValue& r) {
    const StyleValue* re = l.kind == Kind::RegExp ? &l : r.kind == Kind::RegExp ? &r : nullptr;
    const StyleValue* s = l.kind == Kind::String ? &l : r.kind == Kind::String ? &r : nullptr;
    if (!re || !s) badOperands(p, n, l, &r, "a string and a regExp");
    const bool found = std::regex_search(s->string, re->regExp->regex);
    return StyleValue::ofBool(n.op == Op::Match ? found : !found);
}

StyleValue unary(const Program& p, const Node& n, StyleValue v) {
    if (n.op == Op::Not) {
        if (v.kind != Kind::Boolean) badOperands(p, n, v, nullptr, "a Boolean");
        v.boolean = !v.boolean;
        return v;
    }
    if (!v.isNumber() && !v.isVector()) badOperands(p, n, v, nullptr, "a number or a vector");
    if (n.op == Op::Neg)
        for (double& c : v.v) c = -c;
    return v;
}

bool boolean(const Program& p, const Node& n, const StyleValue& v, const char* what) {
    if (v.kind != Kind::Boolean) p.fail(n.pos, std::string(what) + " must be a Boolean, not " + styleKindName(v.kind));
    return v.boolean;
}

StyleValue reference(const Program& p, const Node& n, const EvalContext& ctx) {
    if (n.define) {
        if (ctx.lookup) return n.define->evaluate(*ctx.lookup);
        return ctx.feature ? n.define->evaluate(*ctx.feature) : StyleValue::undefined();
    }
    const PropertyValue* v = nullptr;
    if (ctx.lookup)
        v = (*ctx.lookup)(p.names[size_t(n.value)]);
    else if (ctx.feature && n.slot >= 0)
        v = ctx.feature->property(n.slot);
    return StyleValue::fromProperty(v);
}

StyleValue component(const Program& p, const Node& n, const StyleValue& v, double index) {
    if (!v.isVector()) p.fail(n.pos, std::string("a ") + styleKindName(v.kind) + " has no components");
    if (!(index >= 0 && index < v.size()) || index != std::floor(index)) return StyleValue::undefined();
    return StyleValue::ofNumber(v.v[size_t(index)]);
}

StyleValue call(const Program& p, const Node& n, const EvalContext& ctx) {
    StyleValue args[4];  // no function takes more (vec4, rgba, hsla)
    for (int i = 0; i < n.argCount; ++i) args[i] = evaluateNode(p, p.args[size_t(n.firstArg + i)], ctx);
    return callFunction(p, n.pos, n.fn, args, n.argCount);
}

}  // namespace

StyleValue evaluateNode(const Program& p, int index, const EvalContext& ctx) {
    const Node& n = p.nodes[size_t(index)];
    switch (n.op) {
        case Op::Const: return p.constants[size_t(n.value)];
        case Op::Ref: return reference(p, n, ctx);
        case Op::Neg:
        case Op::Plus:
        case Op::Not: return unary(p, n, evaluateNode(p, n.a, ctx));
        case Op::And:
        case Op::Or: {
            // Short-circuit: the right side is not evaluated when the left decides.
            const bool left = boolean(p, n, evaluateNode(p, n.a, ctx), "the left side of a logical operator");
            if (left == (n.op == Op::Or)) return StyleValue::ofBool(left);
            return StyleValue::ofBool(boolean(p, n, evaluateNode(p, n.b, ctx), "the right side of a logical operator"));
        }
        case Op::Cond: {
            const bool c = boolean(p, n, evaluateNode(p, n.a, ctx), "the condition of '?:'");
            return evaluateNode(p, c ? n.b : n.c, ctx);
        }
        case Op::Call: return call(p, n, ctx);
        case Op::Member: return component(p, n, evaluateNode(p, n.a, ctx), n.value);
        case Op::Index: {
            const StyleValue v = evaluateNode(p, n.a, ctx);
            const StyleValue i = evaluateNode(p, n.b, ctx);
            if (!i.isNumber()) p.fail(n.pos, std::string("an index must be a Number, not ") + styleKindName(i.kind));
            return component(p, n, v, i.number());
        }
        default: break;
    }
    const StyleValue l = evaluateNode(p, n.a, ctx);
    const StyleValue r = evaluateNode(p, n.b, ctx);
    switch (n.op) {
        case Op::Eq: return StyleValue::ofBool(l.strictEquals(r));
        case Op::Ne: return StyleValue::ofBool(!l.strictEquals(r));
        case Op::Lt:
        case Op::Le:
        case Op::Gt:
        case Op::Ge: return compare(p, n, l, r);
        case Op::Match:
        case Op::NoMatch: return match(p, n, l, r);
        default: return arithmetic(p, n, l, r);
    }
}

}  // namespace sg::style
