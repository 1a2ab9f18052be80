#include "sg/style/StyleExpression.h"

#include "sg/style/internal/StyleProgram.h"

namespace sg {

using style::Node;
using style::Op;
using Kind = StyleValue::Kind;

StyleExpression::StyleExpression() : StyleExpression("undefined") {}

StyleExpression::StyleExpression(const std::string& text) : p_(std::make_unique<style::Program>()) {
    p_->text = text;
    style::parseProgram(*p_);
}

StyleExpression::StyleExpression(const StyleExpression& o) : p_(std::make_unique<style::Program>(*o.p_)) {}
StyleExpression::StyleExpression(StyleExpression&& o) noexcept = default;
StyleExpression& StyleExpression::operator=(const StyleExpression& o) {
    if (this != &o) p_ = std::make_unique<style::Program>(*o.p_);
    return *this;
}
StyleExpression& StyleExpression::operator=(StyleExpression&& o) noexcept = default;
StyleExpression::~StyleExpression() = default;

const std::string& StyleExpression::text() const { return p_->text; }
const std::vector<std::string>& StyleExpression::names() const { return p_->names; }

namespace {

bool numeric(Kind k) { return k == Kind::Number || k == Kind::Vec2 || k == Kind::Vec3 || k == Kind::Vec4; }

// Whether an operand of kind `k` can never suit `op` (on the side `left`, for =~ and ===, `other` the kind of
// the other operand when it is a constant).
bool unsuitable(Op op, Kind k, const std::optional<Kind>& other) {
    switch (op) {
        case Op::Neg:
        case Op::Plus:
        case Op::Sub:
        case Op::Mul:
        case Op::Div:
        case Op::Mod:
        case Op::Lt:
        case Op::Le:
        case Op::Gt:
        case Op::Ge: return !numeric(k);
        case Op::Not:
        case Op::And:
        case Op::Or:
        case Op::Cond: return k != Kind::Boolean;
        case Op::Match:
        case Op::NoMatch: return k != Kind::String;
        case Op::Eq:
        case Op::Ne: return other && *other != Kind::Null && *other != Kind::Undefined && *other != k;
        default: return false;
    }
}

}  // namespace

void StyleExpression::bind(const StyleBinder& binder) {
    std::vector<StyleBinding> bindings;
    bindings.reserve(p_->names.size());
    for (const std::string& name : p_->names) bindings.push_back(binder(name));
    for (Node& n : p_->nodes) {
        if (n.op != Op::Ref) continue;
        const StyleBinding& b = bindings[size_t(n.value)];
        n.slot = b.slot;
        n.define = b.define;
    }
    // A typed property used where its kind never fits: reported at the reference, before any feature is styled.
    auto refKind = [&](int i) -> std::optional<Kind> {
        if (i < 0) return std::nullopt;
        const Node& r = p_->nodes[size_t(i)];
        if (r.op == Op::Const) return p_->constants[size_t(r.value)].kind;
        return r.op == Op::Ref && !r.define ? bindings[size_t(r.value)].kind : std::nullopt;
    };
    for (const Node& n : p_->nodes) {
        if (n.op == Op::Const || n.op == Op::Ref || n.op == Op::Call || n.op == Op::Member || n.op == Op::Index)
            continue;
        const int operands[2] = {n.a, n.op == Op::Cond ? -1 : n.b};
        for (int side = 0; side < 2; ++side) {
            const int i = operands[side];
            if (i < 0 || p_->nodes[size_t(i)].op != Op::Ref) continue;
            const std::optional<Kind> k = refKind(i);
            if (!k || !unsuitable(n.op, *k, refKind(operands[1 - side]))) continue;
            const std::string& name = p_->names[size_t(p_->nodes[size_t(i)].value)];
            p_->fail(p_->nodes[size_t(i)].pos, "${" + name + "} is a " + styleKindName(*k) +
                                                   ", which the operator at " + std::to_string(n.pos) + " cannot take");
        }
    }
}

StyleValue StyleExpression::evaluate(const StyleFeature& feature) const {
    style::EvalContext ctx;
    ctx.feature = &feature;
    return style::evaluateNode(*p_, p_->root, ctx);
}

StyleValue StyleExpression::evaluate(const StyleLookup& lookup) const {
    style::EvalContext ctx;
    ctx.lookup = &lookup;
    return style::evaluateNode(*p_, p_->root, ctx);
}

}  // namespace sg
