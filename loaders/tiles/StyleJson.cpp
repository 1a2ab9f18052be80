#include "loaders/tiles/StyleJson.h"

#include "sg/style/StyleValue.h"

#include <nlohmann/json.hpp>

namespace sg {

namespace {

using json = nlohmann::json;

struct Reader {
    const std::string& file;
    std::vector<std::string>* warnings;

    [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
        throw LoadError(file, path, reason);
    }
    void warn(const std::string& path, const std::string& what) const {
        if (warnings) warnings->push_back(path + ": " + what);
    }

    // A string is an expression; a boolean or number (where `scalars` allows) stands for the same literal.
    StyleExpression expression(const json& j, const std::string& path, bool scalars) const {
        std::string text;
        if (j.is_string())
            text = j.get<std::string>();
        else if (scalars && j.is_boolean())
            text = j.get<bool>() ? "true" : "false";
        else if (scalars && j.is_number())
            text = styleNumberString(j.get<double>());
        else
            fail(path, std::string("must be an expression (a string), not ") + j.type_name());
        try {
            return StyleExpression(text);
        } catch (const StyleError& e) {
            fail(path, e.what());
        }
    }

    StyleRule rule(const json& j, const std::string& path, bool scalars) const {
        if (!j.is_object()) return StyleRule(expression(j, path, scalars));
        for (const auto& [key, value] : j.items())
            if (key != "conditions") warn(path + "." + key, "not a member of a conditions object: left out");
        const auto c = j.find("conditions");
        if (c == j.end() || !c->is_array()) fail(path + ".conditions", "must be an array of [condition, expression]");
        std::vector<std::pair<StyleExpression, StyleExpression>> conditions;
        for (size_t i = 0; i < c->size(); ++i) {
            const std::string at = path + ".conditions[" + std::to_string(i) + "]";
            const json& pair = (*c)[i];
            if (!pair.is_array() || pair.size() != 2) fail(at, "must be an array of [condition, expression]");
            conditions.emplace_back(expression(pair[0], at + "[0]", true), expression(pair[1], at + "[1]", true));
        }
        return StyleRule(std::move(conditions));
    }
};

}  // namespace

Style parseStyleJson(const std::string& file, const std::string& text, std::vector<std::string>* warnings) {
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded()) throw LoadError(file, "", "not JSON");
    if (!j.is_object()) throw LoadError(file, "", "a style must be a JSON object");
    const Reader r{file, warnings};
    Style style;
    for (const auto& [key, value] : j.items()) {
        if (key == "show") {
            style.setShow(r.rule(value, key, true));
        } else if (key == "color") {
            style.setColor(r.rule(value, key, false));
        } else if (key == "pointSize") {
            style.setPointSize(r.rule(value, key, true));
        } else if (key == "defines") {
            if (!value.is_object()) r.fail(key, "must be an object of name: expression");
            for (const auto& [name, e] : value.items()) style.setDefine(name, r.expression(e, key + "." + name, true));
        } else if (key != "extras") {
            r.warn(key, key == "meta" ? "meta properties are not read: left out" : "not a style member: left out");
        }
    }
    return style;
}

}  // namespace sg
