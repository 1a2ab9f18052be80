// The metadata JSON reader's values, overrides and property tables (loaders/metadata/internal/MetadataJson.h), and
// the member readers its schema half shares (internal/MetadataFields.h).
#include "loaders/metadata/internal/MetadataFields.h"

#include <cmath>
#include <cstdint>
#include <limits>

namespace sg::metadata {

using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

namespace fields {

void fail(const Context& c, const std::string& path, const std::string& reason) {
    throw LoadError(c.file, path, reason);
}

const json* member(const json& o, const char* key) {
    if (!o.is_object()) return nullptr;
    const auto it = o.find(key);
    return it == o.end() ? nullptr : &*it;
}

std::string text(const json& o, const char* key, const Context& c, const std::string& path, bool required) {
    const json* v = member(o, key);
    if (!v) {
        if (required) fail(c, path + "." + key, "missing");
        return {};
    }
    if (!v->is_string()) fail(c, path + "." + key, "not a string");
    return v->get<std::string>();
}

bool flag(const json& o, const char* key, const Context& c, const std::string& path) {
    const json* v = member(o, key);
    if (!v) return false;
    if (!v->is_boolean()) fail(c, path + "." + key, "not a boolean");
    return v->get<bool>();
}

Leaf leafOf(const ClassProperty& p) {
    switch (p.type) {
        case PropertyType::String:
        case PropertyType::Enum: return Leaf::String;
        case PropertyType::Boolean: return Leaf::Boolean;
        default: return Leaf::Number;
    }
}

namespace {

void checkLeaf(const json& v, Leaf leaf, const Context& c, const std::string& path) {
    const bool ok = leaf == Leaf::Number ? v.is_number() : leaf == Leaf::String ? v.is_string() : v.is_boolean();
    if (!ok)
        fail(c, path, leaf == Leaf::Number ? "not a number" : leaf == Leaf::String ? "not a string" : "not a boolean");
}

void checkElement(const json& v, const ClassProperty& p, Leaf leaf, const Context& c, const std::string& path) {
    const bool vector = p.type >= PropertyType::Vec2 && p.type <= PropertyType::Mat4;
    if (!vector) return checkLeaf(v, leaf, c, path);
    const size_t n = size_t(componentCount(p.type));
    if (!v.is_array() || v.size() != n)
        fail(c, path, std::string("not an array of ") + std::to_string(n) + " for a " + propertyTypeName(p.type));
    for (size_t i = 0; i < n; ++i) checkLeaf(v[i], leaf, c, path + "[" + std::to_string(i) + "]");
}

}  // namespace

void checkShape(const json& v, const ClassProperty& p, Leaf leaf, const Context& c, const std::string& path) {
    if (!p.array) return checkElement(v, p, leaf, c, path);
    if (!v.is_array()) fail(c, path, "not an array, for an array property");
    if (p.count > 0 && v.size() != p.count)
        fail(c, path, "an array of " + std::to_string(v.size()) + ", for an array of " + std::to_string(p.count));
    for (size_t i = 0; i < v.size(); ++i) checkElement(v[i], p, leaf, c, path + "[" + std::to_string(i) + "]");
}

}  // namespace fields

using namespace fields;

PropertyValue valueOf(const json& j) {
    switch (j.type()) {
        case json::value_t::boolean: return PropertyValue::ofBool(j.get<bool>());
        case json::value_t::number_integer: return PropertyValue::ofInt(j.get<int64_t>());
        case json::value_t::number_unsigned: {
            // nlohmann reads every non-negative integer as unsigned: Integer while it fits, for one kind per number.
            const uint64_t u = j.get<uint64_t>();
            if (u <= uint64_t(std::numeric_limits<int64_t>::max())) return PropertyValue::ofInt(int64_t(u));
            return PropertyValue::ofUInt(u);
        }
        case json::value_t::number_float: return PropertyValue::ofNumber(j.get<double>());
        case json::value_t::string: return PropertyValue::ofString(j.get<std::string>());
        case json::value_t::array: {
            std::vector<PropertyValue> items;
            items.reserve(j.size());
            for (const json& item : j) items.push_back(valueOf(item));
            return PropertyValue::ofArray(std::move(items));
        }
        default: return {};
    }
}

json jsonOf(const PropertyValue& v) {
    using Kind = PropertyValue::Kind;
    switch (v.kind) {
        case Kind::Null: return nullptr;
        case Kind::Boolean: return v.boolean;
        case Kind::Integer: return v.integer;
        case Kind::Unsigned: return v.unsignedInteger;
        case Kind::Number: return std::isfinite(v.number) ? json(v.number) : json(nullptr);
        case Kind::String: return v.string;
        case Kind::Array: {
            json a = json::array();
            for (const PropertyValue& item : v.items) a.push_back(jsonOf(item));
            return a;
        }
    }
    return nullptr;
}

namespace {

bool numeric(const ClassProperty& p) { return p.type <= PropertyType::Mat4; }

bool isFloat(ComponentType t) { return t == ComponentType::Float32 || t == ComponentType::Float64; }

// offset, scale, min or max: numbers shaped as the property's values. offset and scale only where the spec allows
// them (FLOAT32/FLOAT64 or normalized; not on a variable-length array, whose elements have no fixed place).
PropertyValue transformMember(const json& o, const char* key, const ClassProperty& p, const Context& c,
                              const std::string& path) {
    const json* v = member(o, key);
    if (!v) return {};
    const std::string at = path + "." + key;
    const bool affine = key[0] == 'o' || key[0] == 's';
    if (!numeric(p)) fail(c, at, std::string("not allowed for a ") + propertyTypeName(p.type));
    if (affine && !isFloat(p.componentType) && !p.normalized)
        fail(c, at,
             std::string("only for FLOAT32, FLOAT64 or normalized properties, not ") +
                 componentTypeName(p.componentType));
    if (p.array && p.count == 0) fail(c, at, "not allowed for a variable-length array");
    checkShape(*v, p, Leaf::Number, c, at);
    return valueOf(*v);
}

ComponentType offsetType(const json& o, const char* key, const Context& c, const std::string& path) {
    const std::string s = text(o, key, c, path);
    if (s.empty()) return ComponentType::UInt32;
    const auto t = parseComponentType(s);
    if (!t || (*t != ComponentType::UInt8 && *t != ComponentType::UInt16 && *t != ComponentType::UInt32 &&
               *t != ComponentType::UInt64))
        fail(c, path + "." + key, "'" + s + "' is not UINT8, UINT16, UINT32 or UINT64");
    return *t;
}

ByteSpan viewOf(const json& o, const char* key, const ViewLookup& view, const Context& c, const std::string& path) {
    const json* v = member(o, key);
    if (!v) return {};
    const std::string at = path + "." + key;
    if (!v->is_number_integer()) fail(c, at, "not a bufferView index");
    return view(v->get<int64_t>(), at);
}

PropertyColumn parseColumn(const json& j, int index, const ClassProperty& p, const ViewLookup& view, const Context& c,
                           const std::string& path) {
    if (!j.is_object()) fail(c, path, "not an object");
    PropertyColumn col;
    col.property = index;
    if (!member(j, "values")) fail(c, path + ".values", "missing");
    col.values = viewOf(j, "values", view, c, path);
    col.arrayOffsets = viewOf(j, "arrayOffsets", view, c, path);
    col.stringOffsets = viewOf(j, "stringOffsets", view, c, path);
    col.arrayOffsetType = offsetType(j, "arrayOffsetType", c, path);
    col.stringOffsetType = offsetType(j, "stringOffsetType", c, path);
    if (p.array && p.count == 0 && !col.arrayOffsets.present())
        fail(c, path + ".arrayOffsets", "missing, for a variable-length array");
    if (p.type == PropertyType::String && !col.stringOffsets.present())
        fail(c, path + ".stringOffsets", "missing, for a STRING property");
    col.overrides = parseOverrides(j, p, c, path);
    return col;
}

}  // namespace

PropertyOverrides parseOverrides(const json& j, const ClassProperty& p, const Context& c, const std::string& path) {
    PropertyOverrides o;
    o.offset = transformMember(j, "offset", p, c, path);
    o.scale = transformMember(j, "scale", p, c, path);
    o.min = transformMember(j, "min", p, c, path);
    o.max = transformMember(j, "max", p, c, path);
    return o;
}

PropertyTable parsePropertyTable(const json& j, const Schema& schema, const ViewLookup& view, const Context& c,
                                 const std::string& path) {
    if (!j.is_object()) fail(c, path, "not an object");
    PropertyTable t;
    t.name = text(j, "name", c, path);
    const std::string cls = text(j, "class", c, path, true);
    t.classIndex = schema.findClass(cls);
    if (t.classIndex < 0) fail(c, path + ".class", "no class '" + cls + "' in the schema");
    const json* count = member(j, "count");
    if (!count) fail(c, path + ".count", "missing");
    if (!count->is_number_unsigned() && !(count->is_number_integer() && count->get<int64_t>() >= 0))
        fail(c, path + ".count", "not a count");
    t.count = count->get<uint64_t>();

    const ClassDef& def = schema.classes[size_t(t.classIndex)];
    const json* props = member(j, "properties");
    if (props && !props->is_object()) fail(c, path + ".properties", "not an object");
    if (props) {
        for (const auto& [id, column] : props->items()) {
            const std::string at = path + ".properties." + id;
            const int index = def.find(id);
            if (index < 0) {
                c.warn(at, "no property '" + id + "' in class '" + def.id + "', left out");
                continue;
            }
            t.columns.push_back(parseColumn(column, index, def.properties[size_t(index)], view, c, at));
        }
    }
    for (size_t i = 0; i < def.properties.size(); ++i)
        if (def.properties[i].required && !t.column(int(i)))
            fail(c, path + ".properties." + def.properties[i].id, "missing, and class '" + def.id + "' requires it");
    return t;
}

}  // namespace sg::metadata
