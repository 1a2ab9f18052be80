// PropertyValue and the schema's small helpers (sg/core/Properties.h): how a value prints, its JSON, the spelling of
// the spec's type names and the look-ups by id.
#include "sg/core/Properties.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>

namespace sg {

PropertyValue PropertyValue::ofBool(bool b) {
    PropertyValue v;
    v.kind = Kind::Boolean;
    v.boolean = b;
    return v;
}

PropertyValue PropertyValue::ofInt(int64_t i) {
    PropertyValue v;
    v.kind = Kind::Integer;
    v.integer = i;
    return v;
}

PropertyValue PropertyValue::ofUInt(uint64_t u) {
    PropertyValue v;
    v.kind = Kind::Unsigned;
    v.unsignedInteger = u;
    return v;
}

PropertyValue PropertyValue::ofNumber(double d) {
    PropertyValue v;
    v.kind = Kind::Number;
    v.number = d;
    return v;
}

PropertyValue PropertyValue::ofString(std::string s) {
    PropertyValue v;
    v.kind = Kind::String;
    v.string = std::move(s);
    return v;
}

PropertyValue PropertyValue::ofArray(std::vector<PropertyValue> items) {
    PropertyValue v;
    v.kind = Kind::Array;
    v.items = std::move(items);
    return v;
}

double PropertyValue::asNumber() const {
    switch (kind) {
        case Kind::Boolean: return boolean ? 1.0 : 0.0;
        case Kind::Integer: return double(integer);
        case Kind::Unsigned: return double(unsignedInteger);
        case Kind::Number: return number;
        default: return 0.0;
    }
}

namespace {

// The shortest text that reads back as the same double: 0.1 prints "0.1", not "0.10000000000000001" (std::to_chars,
// several times faster than trying printf's precisions: a pick's panel prints every property).
std::string shortest(double d) {
    char buf[64];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, d);
    return std::string(buf, r.ptr);
}

void escapeJson(const std::string& s, std::string& out) {
    out += '"';
    for (char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\b': out += "\\b"; break;
            case '\f': out += "\\f"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            default:
                if (c < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
                    out += buf;
                } else {
                    out += ch;  // UTF-8 passes through as it is
                }
        }
    }
    out += '"';
}

void appendText(const PropertyValue& v, bool json, std::string& out) {
    using Kind = PropertyValue::Kind;
    switch (v.kind) {
        case Kind::Null: out += "null"; break;
        case Kind::Boolean: out += v.boolean ? "true" : "false"; break;
        case Kind::Integer: out += std::to_string(v.integer); break;
        case Kind::Unsigned: out += std::to_string(v.unsignedInteger); break;
        case Kind::Number: out += (json && !std::isfinite(v.number)) ? "null" : shortest(v.number); break;
        case Kind::String:
            if (json)
                escapeJson(v.string, out);
            else
                out += v.string;
            break;
        case Kind::Array:
            out += '[';
            for (size_t i = 0; i < v.items.size(); ++i) {
                if (i) out += json ? "," : ", ";
                appendText(v.items[i], json, out);
            }
            out += ']';
            break;
    }
}

}  // namespace

std::string PropertyValue::toString() const {
    std::string out;
    appendText(*this, false, out);
    return out;
}

std::string PropertyValue::toJson() const {
    std::string out;
    appendText(*this, true, out);
    return out;
}

bool PropertyValue::operator==(const PropertyValue& o) const {
    // An Integer and an Unsigned of the same value are the same number (a JSON 5 and a UINT8 5).
    if (kind == Kind::Integer && o.kind == Kind::Unsigned)
        return integer >= 0 && uint64_t(integer) == o.unsignedInteger;
    if (kind == Kind::Unsigned && o.kind == Kind::Integer) return o == *this;
    if (kind != o.kind) return false;
    switch (kind) {
        case Kind::Null: return true;
        case Kind::Boolean: return boolean == o.boolean;
        case Kind::Integer: return integer == o.integer;
        case Kind::Unsigned: return unsignedInteger == o.unsignedInteger;
        case Kind::Number: return number == o.number;
        case Kind::String: return string == o.string;
        case Kind::Array: return items == o.items;
    }
    return false;
}

int componentCount(PropertyType t) {
    switch (t) {
        case PropertyType::Vec2: return 2;
        case PropertyType::Vec3: return 3;
        case PropertyType::Vec4: return 4;
        case PropertyType::Mat2: return 4;
        case PropertyType::Mat3: return 9;
        case PropertyType::Mat4: return 16;
        default: return 1;
    }
}

int componentBytes(ComponentType c) {
    switch (c) {
        case ComponentType::Int8:
        case ComponentType::UInt8: return 1;
        case ComponentType::Int16:
        case ComponentType::UInt16: return 2;
        case ComponentType::Int32:
        case ComponentType::UInt32:
        case ComponentType::Float32: return 4;
        case ComponentType::Int64:
        case ComponentType::UInt64:
        case ComponentType::Float64: return 8;
        case ComponentType::None: return 0;
    }
    return 0;
}

namespace {

const char* const kTypeNames[] = {"SCALAR", "VEC2", "VEC3",   "VEC4",    "MAT2",
                                  "MAT3",   "MAT4", "STRING", "BOOLEAN", "ENUM"};
const char* const kComponentNames[] = {"",       "INT8",  "UINT8",  "INT16",   "UINT16", "INT32",
                                       "UINT32", "INT64", "UINT64", "FLOAT32", "FLOAT64"};

}  // namespace

const char* propertyTypeName(PropertyType t) { return kTypeNames[size_t(t)]; }
const char* componentTypeName(ComponentType c) { return kComponentNames[size_t(c)]; }

std::optional<PropertyType> parsePropertyType(const std::string& s) {
    for (size_t i = 0; i < std::size(kTypeNames); ++i)
        if (s == kTypeNames[i]) return PropertyType(i);
    return std::nullopt;
}

std::optional<ComponentType> parseComponentType(const std::string& s) {
    for (size_t i = 1; i < std::size(kComponentNames); ++i)  // "" (None) is no spelling of the spec's
        if (s == kComponentNames[i]) return ComponentType(i);
    return std::nullopt;
}

const std::string* EnumDef::nameOf(int64_t value) const {
    for (const auto& [name, v] : values)
        if (v == value) return &name;
    return nullptr;
}

int ClassDef::find(const std::string& propertyId) const {
    for (size_t i = 0; i < properties.size(); ++i)
        if (properties[i].id == propertyId) return int(i);
    return -1;
}

int Schema::findClass(const std::string& classId) const {
    for (size_t i = 0; i < classes.size(); ++i)
        if (classes[i].id == classId) return int(i);
    return -1;
}

int Schema::findEnum(const std::string& enumId) const {
    for (size_t i = 0; i < enums.size(); ++i)
        if (enums[i].id == enumId) return int(i);
    return -1;
}

const PropertyColumn* PropertyTable::column(int property) const {
    for (const PropertyColumn& c : columns)
        if (c.property == property) return &c;
    return nullptr;
}

}  // namespace sg
