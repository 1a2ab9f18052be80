// A 3D Tiles style: whether a feature shows, its colour and its point size, each an expression or a list of
// conditions, with named expressions (defines) they may read as ${name}.
#pragma once
#include "sg/style/StyleExpression.h"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sg {

// One visual property: an expression, or conditions [[condition, expression], ...] of which the first whose
// condition is true gives the value (undefined when none is). Empty: not given (the property's default).
class StyleRule {
public:
    StyleRule() = default;
    explicit StyleRule(StyleExpression expression);
    explicit StyleRule(std::vector<std::pair<StyleExpression, StyleExpression>> conditions);

    bool empty() const { return !single_ && conditions_.empty(); }
    void bind(const StyleBinder& binder);
    // The value, and in `from` (when given) the expression that made it: StyleError when a condition is not a
    // Boolean.
    StyleValue evaluate(const StyleFeature& feature, const StyleExpression** from = nullptr) const;
    StyleValue evaluate(const StyleLookup& lookup, const StyleExpression** from = nullptr) const;
    // The property names its expressions read.
    void collectNames(std::vector<std::string>& names) const;

private:
    template <class F>
    StyleValue run(const F& feature, const StyleExpression** from) const;

    std::optional<StyleExpression> single_;
    std::vector<std::pair<StyleExpression, StyleExpression>> conditions_;
};

// A feature's look under a style: colour RGBA in 0..1.
struct StyleLook {
    bool show = true;
    std::array<float, 4> color{1.0f, 1.0f, 1.0f, 1.0f};
    float pointSize = 1.0f;
};

// Defaults where the style gives nothing or its expression gives undefined: shown, white, point size 1. A value
// of the wrong type (a colour that is not a vec4, a show that is not a Boolean) is a StyleError.
class Style {
public:
    Style();
    void setShow(StyleRule rule);
    void setColor(StyleRule rule);
    void setPointSize(StyleRule rule);
    // A define: ${name} in show, color and pointSize stands for it. A define reads properties only (a ${name}
    // in it is the property, even when a define has that name).
    void setDefine(const std::string& name, StyleExpression expression);

    // Numbers the properties the style reads through `binder` (StyleExpression::bind), as for the features to
    // be evaluated; until then, by name only (the StyleLookup overloads).
    void bind(StyleBinder binder);
    // The property names read, each once (defines' own included, names of defines excluded).
    std::vector<std::string> names() const;

    StyleLook evaluate(const StyleFeature& feature) const;
    StyleLook evaluate(const StyleLookup& lookup) const;

private:
    void relink();
    template <class F>
    StyleLook look(const F& feature) const;

    StyleRule show_, color_, pointSize_;
    std::vector<std::pair<std::string, StyleExpression>> defineSources_;
    // The defines as bound, shared by copies of a style: a new binding makes new ones, never changes these.
    std::vector<std::shared_ptr<const StyleExpression>> defines_;
    StyleBinder binder_;
};

}  // namespace sg
