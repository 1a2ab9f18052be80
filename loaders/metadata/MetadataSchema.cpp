// A metadata schema read from its JSON and written back (loaders/metadata/internal/MetadataJson.h): enums first,
// since class properties name them; every property checked against its type where it is read.
#include "loaders/metadata/internal/MetadataFields.h"

#include <algorithm>
#include <cstdint>
#include <set>

namespace sg::metadata {

using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)
using namespace fields;

namespace {

bool isIntegerType(ComponentType t) {
    return t != ComponentType::None && t != ComponentType::Float32 && t != ComponentType::Float64;
}

// Whether an enum value fits its value type (64-bit ones: any integer JSON gives, unsigned ones not negative).
bool fits(int64_t n, bool fromUnsigned, ComponentType t) {
    switch (t) {
        case ComponentType::Int8: return n >= INT8_MIN && n <= INT8_MAX;
        case ComponentType::UInt8: return n >= 0 && n <= UINT8_MAX;
        case ComponentType::Int16: return n >= INT16_MIN && n <= INT16_MAX;
        case ComponentType::UInt16: return n >= 0 && n <= UINT16_MAX;
        case ComponentType::Int32: return n >= INT32_MIN && n <= INT32_MAX;
        case ComponentType::UInt32: return n >= 0 && n <= int64_t(UINT32_MAX);
        case ComponentType::Int64: return !fromUnsigned || n >= 0;
        case ComponentType::UInt64: return fromUnsigned || n >= 0;
        default: return false;
    }
}

EnumDef parseEnum(const std::string& id, const json& j, const Context& c, const std::string& path) {
    if (!j.is_object()) fail(c, path, "not an object");
    EnumDef e;
    e.id = id;
    e.name = text(j, "name", c, path);
    const std::string valueType = text(j, "valueType", c, path);
    if (!valueType.empty()) {
        const auto t = parseComponentType(valueType);
        if (!t || !isIntegerType(*t)) fail(c, path + ".valueType", "'" + valueType + "' is not an integer type");
        e.valueType = *t;
    }
    const json* values = member(j, "values");
    if (!values || !values->is_array() || values->empty()) fail(c, path + ".values", "not a non-empty array");
    std::set<std::string> names;
    std::set<int64_t> seen;
    for (size_t i = 0; i < values->size(); ++i) {
        const std::string at = path + ".values[" + std::to_string(i) + "]";
        const json& v = (*values)[i];
        const std::string name = text(v, "name", c, at, true);
        const json* value = member(v, "value");
        if (!value || !value->is_number_integer()) fail(c, at + ".value", "not an integer");
        // A UINT64 value past INT64_MAX is kept by its bits, as the store reads it.
        const int64_t n = value->is_number_unsigned() ? int64_t(value->get<uint64_t>()) : value->get<int64_t>();
        if (!fits(n, value->is_number_unsigned(), e.valueType))
            fail(c, at + ".value", std::to_string(n) + " does not fit " + componentTypeName(e.valueType));
        if (!names.insert(name).second) fail(c, at + ".name", "'" + name + "' named twice");
        if (!seen.insert(n).second) fail(c, at + ".value", std::to_string(n) + " given twice");
        e.values.emplace_back(name, n);
    }
    return e;
}

// type, componentType, enumType: what the property's values are.
void parseType(const json& j, ClassProperty& p, const Schema& s, const Context& c, const std::string& path) {
    const std::string type = text(j, "type", c, path, true);
    const auto t = parsePropertyType(type);
    if (!t) fail(c, path + ".type", "unknown type '" + type + "'");
    p.type = *t;
    if (p.type == PropertyType::Enum) {
        const std::string enumType = text(j, "enumType", c, path, true);
        p.enumIndex = s.findEnum(enumType);
        if (p.enumIndex < 0) fail(c, path + ".enumType", "no enum '" + enumType + "' in the schema");
        p.componentType = s.enums[size_t(p.enumIndex)].valueType;  // the enum's value type is the stored one
    } else if (p.type <= PropertyType::Mat4) {
        const std::string ct = text(j, "componentType", c, path, true);
        const auto parsed = parseComponentType(ct);
        if (!parsed) fail(c, path + ".componentType", "unknown componentType '" + ct + "'");
        p.componentType = *parsed;
    }
}

void parseArray(const json& j, ClassProperty& p, const Context& c, const std::string& path) {
    p.array = flag(j, "array", c, path);
    const json* count = member(j, "count");
    if (!count) return;
    if (!p.array) {
        c.warn(path + ".count", "count without array: left out");
        return;
    }
    // A signed integer (a document built in code rather than parsed) counts as well as an unsigned one.
    const bool integer = count->is_number_unsigned() || (count->is_number_integer() && count->get<int64_t>() >= 0);
    if (!integer || count->get<uint64_t>() < 2 || count->get<uint64_t>() > UINT32_MAX)
        fail(c, path + ".count", "not an integer of at least 2");
    p.count = uint32_t(count->get<uint64_t>());
}

// noData or default: shaped as the values; an enum's by name, a name the enum has.
PropertyValue special(const json& j, const char* key, const ClassProperty& p, const Schema& s, const Context& c,
                      const std::string& path) {
    const json* v = member(j, key);
    if (!v) return {};
    const std::string at = path + "." + key;
    if (key[0] == 'n' && p.type == PropertyType::Boolean) fail(c, at, "not allowed for a BOOLEAN");
    // A normalized property's default is the final value (a number); its noData the raw one: both numbers.
    checkShape(*v, p, leafOf(p), c, at);
    PropertyValue value = valueOf(*v);
    if (p.type == PropertyType::Enum) {
        const EnumDef& e = s.enums[size_t(p.enumIndex)];
        const auto named = [&](const PropertyValue& name) {
            return std::any_of(e.values.begin(), e.values.end(),
                               [&](const auto& nv) { return nv.first == name.string; });
        };
        const bool ok = value.kind == PropertyValue::Kind::Array
                            ? std::all_of(value.items.begin(), value.items.end(), named)
                            : named(value);
        if (!ok) fail(c, at, "names a value enum '" + e.id + "' does not have");
    }
    return value;
}

ClassProperty parseProperty(const std::string& id, const json& j, const Schema& s, const Context& c,
                            const std::string& path) {
    if (!j.is_object()) fail(c, path, "not an object");
    ClassProperty p;
    p.id = id;
    p.name = text(j, "name", c, path);
    p.description = text(j, "description", c, path);
    parseType(j, p, s, c, path);
    parseArray(j, p, c, path);
    p.normalized = flag(j, "normalized", c, path);
    if (p.normalized && (p.type > PropertyType::Mat4 || !isIntegerType(p.componentType)))
        fail(c, path + ".normalized",
             std::string("only for integer component types, not ") +
                 (p.type > PropertyType::Mat4 ? propertyTypeName(p.type) : componentTypeName(p.componentType)));
    p.required = flag(j, "required", c, path);
    const PropertyOverrides o = parseOverrides(j, p, c, path);
    p.offset = o.offset;
    p.scale = o.scale;
    p.min = o.min;
    p.max = o.max;
    p.noData = special(j, "noData", p, s, c, path);
    p.defaultValue = special(j, "default", p, s, c, path);
    return p;
}

ClassDef parseClass(const std::string& id, const json& j, const Schema& s, const Context& c, const std::string& path) {
    if (!j.is_object()) fail(c, path, "not an object");
    ClassDef cls;
    cls.id = id;
    cls.name = text(j, "name", c, path);
    cls.description = text(j, "description", c, path);
    const json* props = member(j, "properties");
    if (!props) return cls;
    if (!props->is_object()) fail(c, path + ".properties", "not an object");
    for (const auto& [pid, pj] : props->items())
        cls.properties.push_back(parseProperty(pid, pj, s, c, path + ".properties." + pid));
    return cls;
}

}  // namespace

Schema parseSchema(const json& j, const Context& c, const std::string& path) {
    if (!j.is_object()) fail(c, path, "not an object");
    Schema s;
    s.id = text(j, "id", c, path);
    s.name = text(j, "name", c, path);
    s.version = text(j, "version", c, path);
    // Keyed by id; nlohmann::ordered_json keeps keys sorted, so classes, enums and properties come in the order of
    // their ids.
    if (const json* enums = member(j, "enums")) {
        if (!enums->is_object()) fail(c, path + ".enums", "not an object");
        for (const auto& [id, e] : enums->items()) s.enums.push_back(parseEnum(id, e, c, path + ".enums." + id));
    }
    if (const json* classes = member(j, "classes")) {
        if (!classes->is_object()) fail(c, path + ".classes", "not an object");
        for (const auto& [id, cj] : classes->items())
            s.classes.push_back(parseClass(id, cj, s, c, path + ".classes." + id));
    }
    return s;
}

namespace {

void putText(json& o, const char* key, const std::string& s) {
    if (!s.empty()) o[key] = s;
}

void putValue(json& o, const char* key, const PropertyValue& v) {
    if (!v.isNull()) o[key] = jsonOf(v);
}

json propertyJson(const ClassProperty& p, const Schema& s) {
    json o = json::object();
    putText(o, "name", p.name);
    putText(o, "description", p.description);
    o["type"] = propertyTypeName(p.type);
    if (p.type == PropertyType::Enum && p.enumIndex >= 0 && size_t(p.enumIndex) < s.enums.size())
        o["enumType"] = s.enums[size_t(p.enumIndex)].id;
    else if (p.type <= PropertyType::Mat4 && p.componentType != ComponentType::None)
        o["componentType"] = componentTypeName(p.componentType);
    if (p.array) o["array"] = true;
    if (p.array && p.count > 0) o["count"] = p.count;
    if (p.normalized) o["normalized"] = true;
    if (p.required) o["required"] = true;
    putValue(o, "offset", p.offset);
    putValue(o, "scale", p.scale);
    putValue(o, "min", p.min);
    putValue(o, "max", p.max);
    putValue(o, "noData", p.noData);
    putValue(o, "default", p.defaultValue);
    return o;
}

}  // namespace

json schemaJson(const Schema& s) {
    json o = json::object();
    putText(o, "id", s.id);
    putText(o, "name", s.name);
    putText(o, "version", s.version);
    if (!s.enums.empty()) {
        json enums = json::object();
        for (const EnumDef& e : s.enums) {
            json ej = json::object();
            putText(ej, "name", e.name);
            ej["valueType"] = componentTypeName(e.valueType);
            json values = json::array();
            for (const auto& [name, value] : e.values) values.push_back({{"name", name}, {"value", value}});
            ej["values"] = std::move(values);
            enums[e.id] = std::move(ej);
        }
        o["enums"] = std::move(enums);
    }
    if (!s.classes.empty()) {
        json classes = json::object();
        for (const ClassDef& cls : s.classes) {
            json cj = json::object();
            putText(cj, "name", cls.name);
            putText(cj, "description", cls.description);
            json props = json::object();
            for (const ClassProperty& p : cls.properties) props[p.id] = propertyJson(p, s);
            cj["properties"] = std::move(props);
            classes[cls.id] = std::move(cj);
        }
        o["classes"] = std::move(classes);
    }
    return o;
}

}  // namespace sg::metadata
