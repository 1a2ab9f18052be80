#include "sg/style/Style.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace sg {

using Kind = StyleValue::Kind;

StyleRule::StyleRule(StyleExpression expression) : single_(std::move(expression)) {}

StyleRule::StyleRule(std::vector<std::pair<StyleExpression, StyleExpression>> conditions)
    : conditions_(std::move(conditions)) {}

void StyleRule::bind(const StyleBinder& binder) {
    if (single_) single_->bind(binder);
    for (auto& [condition, expression] : conditions_) {
        condition.bind(binder);
        expression.bind(binder);
    }
}

template <class F>
StyleValue StyleRule::run(const F& feature, const StyleExpression** from) const {
    if (from) *from = single_ ? &*single_ : nullptr;
    if (single_) return single_->evaluate(feature);
    for (const auto& [condition, expression] : conditions_) {
        const StyleValue c = condition.evaluate(feature);
        if (c.kind != Kind::Boolean)
            throw StyleError(condition.text(), 0,
                             std::string("a condition must be a Boolean, not ") + styleKindName(c.kind));
        if (!c.boolean) continue;
        if (from) *from = &expression;
        return expression.evaluate(feature);
    }
    return StyleValue::undefined();
}

StyleValue StyleRule::evaluate(const StyleFeature& feature, const StyleExpression** from) const {
    return run(feature, from);
}

StyleValue StyleRule::evaluate(const StyleLookup& lookup, const StyleExpression** from) const {
    return run(lookup, from);
}

void StyleRule::collectNames(std::vector<std::string>& names) const {
    auto add = [&names](const StyleExpression& e) {
        for (const std::string& n : e.names())
            if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    };
    if (single_) add(*single_);
    for (const auto& [condition, expression] : conditions_) {
        add(condition);
        add(expression);
    }
}

Style::Style() : binder_([](const std::string&) { return StyleBinding{}; }) {}

void Style::setShow(StyleRule rule) {
    show_ = std::move(rule);
    relink();
}

void Style::setColor(StyleRule rule) {
    color_ = std::move(rule);
    relink();
}

void Style::setPointSize(StyleRule rule) {
    pointSize_ = std::move(rule);
    relink();
}

void Style::setDefine(const std::string& name, StyleExpression expression) {
    auto it =
        std::find_if(defineSources_.begin(), defineSources_.end(), [&](const auto& d) { return d.first == name; });
    if (it != defineSources_.end())
        it->second = std::move(expression);
    else
        defineSources_.emplace_back(name, std::move(expression));
    relink();
}

void Style::bind(StyleBinder binder) {
    binder_ = std::move(binder);
    relink();
}

// Binds the defines (new copies: copies of this style may still read the old ones) and then the rules, a name
// being a define's before it is a property's.
void Style::relink() {
    defines_.clear();
    for (const auto& [name, expression] : defineSources_) {
        auto d = std::make_shared<StyleExpression>(expression);
        d->bind(binder_);
        defines_.push_back(std::move(d));
    }
    const StyleBinder withDefines = [this](const std::string& name) {
        for (size_t i = 0; i < defineSources_.size(); ++i)
            if (defineSources_[i].first == name) return StyleBinding{-1, std::nullopt, defines_[i].get()};
        return binder_(name);
    };
    show_.bind(withDefines);
    color_.bind(withDefines);
    pointSize_.bind(withDefines);
}

std::vector<std::string> Style::names() const {
    std::vector<std::string> all, out;
    show_.collectNames(all);
    color_.collectNames(all);
    pointSize_.collectNames(all);
    for (const std::string& n : all)
        if (std::none_of(defineSources_.begin(), defineSources_.end(), [&](const auto& d) { return d.first == n; }))
            out.push_back(n);
    for (const auto& define : defineSources_)
        for (const std::string& n : define.second.names())
            if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
    return out;
}

namespace {

[[noreturn]] void wrongType(const StyleExpression* from, const char* what, const char* wanted, Kind got) {
    throw StyleError(from ? from->text() : std::string(), 0,
                     std::string(what) + " must be " + wanted + ", not " + styleKindName(got));
}

float unit(double c) { return float(std::fmin(std::fmax(c, 0.0), 1.0)); }  // NaN to 0

}  // namespace

template <class F>
StyleLook Style::look(const F& feature) const {
    StyleLook look;
    const StyleExpression* from = nullptr;
    const StyleValue show = show_.evaluate(feature, &from);
    if (show.kind == Kind::Boolean)
        look.show = show.boolean;
    else if (show.kind != Kind::Undefined)
        wrongType(from, "show", "a Boolean", show.kind);
    if (!look.show) return look;  // a hidden feature's colour and size are never used: not computed
    const StyleValue color = color_.evaluate(feature, &from);
    if (color.kind == Kind::Vec4)
        look.color = {unit(color.v[0]), unit(color.v[1]), unit(color.v[2]), unit(color.v[3])};
    else if (color.kind != Kind::Undefined)
        wrongType(from, "color", "a color (vec4)", color.kind);
    const StyleValue size = pointSize_.evaluate(feature, &from);
    if (size.kind == Kind::Number)
        look.pointSize = float(std::clamp(size.number(), -double(FLT_MAX), double(FLT_MAX)));
    else if (size.kind != Kind::Undefined)
        wrongType(from, "pointSize", "a Number", size.kind);
    return look;
}

StyleLook Style::evaluate(const StyleFeature& feature) const { return look(feature); }
StyleLook Style::evaluate(const StyleLookup& lookup) const { return look(lookup); }

}  // namespace sg
