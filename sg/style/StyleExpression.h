// One expression of the 3D Tiles styling language ("${height} > 50 ? color('red') : color('white', 0.5)"), parsed
// once and evaluated for many features.
#pragma once
#include "sg/core/Properties.h"
#include "sg/style/StyleValue.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sg {

namespace style {
struct Program;
}

// A feature as an expression reads it: each ${name} is a slot numbered when the expression was bound (unbound,
// slot i is the expression's names()[i]). Null: the feature has no such property (undefined). The value must
// stay valid until the evaluation returns.
class StyleFeature {
public:
    virtual ~StyleFeature() = default;
    virtual const PropertyValue* property(int slot) const = 0;
};

// A property by name, for an evaluation without binding (tests, a one-off pick).
using StyleLookup = std::function<const PropertyValue*(const std::string& name)>;

class StyleExpression;

// What a binder says of a name: its slot; the kind its values read as when known (a typed property: references
// used with an operator that cannot take that kind are then an error when bound); or the define the name stands
// for, evaluated in its place (it must outlive this expression).
struct StyleBinding {
    int slot = -1;  // -1: no such property (always undefined)
    std::optional<StyleValue::Kind> kind;
    const StyleExpression* define = nullptr;
};
using StyleBinder = std::function<StyleBinding(const std::string& name)>;

class StyleExpression {
public:
    StyleExpression();  // "undefined"
    // Parses `text`: StyleError naming the position of the first mistake. Parts made of constants only
    // (color('red'), regExp('^A')) are computed here, once; one that cannot be computed is an error here.
    explicit StyleExpression(const std::string& text);
    StyleExpression(const StyleExpression& o);
    StyleExpression(StyleExpression&& o) noexcept;
    StyleExpression& operator=(const StyleExpression& o);
    StyleExpression& operator=(StyleExpression&& o) noexcept;
    ~StyleExpression();

    const std::string& text() const;
    // The property names it reads (${name}, ${feature['name']}), each once, in the order of their first use.
    const std::vector<std::string>& names() const;
    // Numbers every reference through `binder`; StyleError at a reference whose known kind an operator cannot
    // take ("${name} < 5" with name a String).
    void bind(const StyleBinder& binder);

    // The value for one feature: StyleError where the spec says an operation fails ('abc' * 2, a condition that
    // is not a Boolean, a property compared that the feature does not have).
    StyleValue evaluate(const StyleFeature& feature) const;
    StyleValue evaluate(const StyleLookup& lookup) const;

private:
    std::unique_ptr<style::Program> p_;
};

}  // namespace sg
