// libFuzzer target for the styling language (sg/style): any bytes, read as one expression and as a style's JSON
// (loaders/tiles/StyleJson.h), bound to a fixed feature's typed properties and evaluated for it, either parse,
// bind and evaluate or throw sg::StyleError (sg::LoadError for the JSON). Anything else (a crash, a sanitizer
// report, another exception, a hang past -timeout, a leak) is a finding. The seed corpus in fuzz/style-corpus/ holds
// expressions and styles of the spec's examples.
#include "loaders/tiles/StyleJson.h"
#include "sg/style/Style.h"
#include "sg/style/StyleExpression.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

struct Property {
    const char* name;
    sg::PropertyValue value;
    sg::StyleValue::Kind kind;
};

sg::PropertyValue number(double d) {
    sg::PropertyValue v;
    v.kind = sg::PropertyValue::Kind::Number;
    v.number = d;
    return v;
}

std::vector<Property> makeFeature() {
    using K = sg::StyleValue::Kind;
    sg::PropertyValue name, count, flag, position, nothing;
    name.kind = sg::PropertyValue::Kind::String;
    name.string = "Main hall";
    count.kind = sg::PropertyValue::Kind::Integer;
    count.integer = 7;
    flag.kind = sg::PropertyValue::Kind::Boolean;
    flag.boolean = true;
    position.kind = sg::PropertyValue::Kind::Array;
    position.items = {number(1.0), number(-2.5), number(3.0)};
    return {{"height", number(42.5), K::Number}, {"name", name, K::String},       {"count", count, K::Number},
            {"flag", flag, K::Boolean},          {"position", position, K::Vec3}, {"nothing", nothing, K::Null}};
}

class Feature final : public sg::StyleFeature {
public:
    explicit Feature(const std::vector<Property>& p) : p_(p) {}
    const sg::PropertyValue* property(int slot) const override {
        return slot >= 0 && size_t(slot) < p_.size() ? &p_[size_t(slot)].value : nullptr;
    }

private:
    const std::vector<Property>& p_;
};

void run(const std::string& text) {
    static const std::vector<Property> properties = makeFeature();
    const Feature feature(properties);
    const sg::StyleBinder binder = [](const std::string& name) {
        for (size_t i = 0; i < properties.size(); ++i)
            if (name == properties[i].name) {
                sg::StyleBinding b;
                b.slot = int(i);
                if (properties[i].kind != sg::StyleValue::Kind::Null) b.kind = properties[i].kind;
                return b;
            }
        return sg::StyleBinding{};
    };
    const sg::StyleLookup lookup = [](const std::string& name) -> const sg::PropertyValue* {
        for (const Property& p : properties)
            if (name == p.name) return &p.value;
        return nullptr;
    };
    try {
        sg::StyleExpression e(text);
        try {
            e.evaluate(lookup).toString();
        } catch (const sg::StyleError&) {
        }
        e.bind(binder);
        e.evaluate(feature).toString();
    } catch (const sg::StyleError&) {
    }
    try {
        sg::Style style = sg::parseStyleJson("fuzz.json", text);
        style.evaluate(lookup);
        style.bind(binder);
        style.evaluate(feature);
    } catch (const sg::StyleError&) {
    } catch (const sg::LoadError&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    // std::regex backtracks, as JavaScript's regular expressions do: a pattern such as (a*)*b takes time
    // exponential in the length of the text it is matched against (and is matched when parsed, its operands
    // being constants). A style is its author's own program; such inputs are left to short ones.
    if (size > 40 && text.find("regExp") != std::string::npos) return 0;
    run(text);
    return 0;
}
