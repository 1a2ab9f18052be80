// Stored bytes to values (sg/core/internal/PropertyDecode.h), by the rules of 3D Tiles 1.1 metadata: little-endian
// components, noData compared against the raw value, normalization then offset + scale * value.
#include "sg/core/internal/PropertyDecode.h"

#include <algorithm>
#include <cstring>
#include <type_traits>

namespace sg::props {

namespace {

template <typename T>
T load(const uint8_t* at) {
    // Byte by byte: the data need not be aligned, and the files are little-endian whatever the host.
    using U = std::conditional_t<
        sizeof(T) == 1, uint8_t,
        std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
    U u = 0;
    for (size_t i = 0; i < sizeof(T); ++i) u |= U(U(at[i]) << (8 * i));
    T t;
    std::memcpy(&t, &u, sizeof t);
    return t;
}

// The largest value of an integer component type: what a normalized value is divided by.
double integerMax(ComponentType c) {
    switch (c) {
        case ComponentType::Int8: return 127.0;
        case ComponentType::UInt8: return 255.0;
        case ComponentType::Int16: return 32767.0;
        case ComponentType::UInt16: return 65535.0;
        case ComponentType::Int32: return 2147483647.0;
        case ComponentType::UInt32: return 4294967295.0;
        case ComponentType::Int64: return 9223372036854775807.0;
        case ComponentType::UInt64: return 18446744073709551615.0;
        default: return 1.0;
    }
}

bool isSigned(ComponentType c) {
    return c == ComponentType::Int8 || c == ComponentType::Int16 || c == ComponentType::Int32 ||
           c == ComponentType::Int64;
}

bool isNumber(const PropertyValue& v) {
    using Kind = PropertyValue::Kind;
    return v.kind == Kind::Integer || v.kind == Kind::Unsigned || v.kind == Kind::Number;
}

// Whether a raw value is the noData one: element by element, integers exactly, FLOAT32 at float precision (the
// schema's noData is written as a double).
bool isNoData(const PropertyValue& raw, const PropertyValue& noData, ComponentType c) {
    using Kind = PropertyValue::Kind;
    if (raw.kind == Kind::Array || noData.kind == Kind::Array) {
        if (raw.kind != noData.kind || raw.items.size() != noData.items.size()) return false;
        for (size_t i = 0; i < raw.items.size(); ++i)
            if (!isNoData(raw.items[i], noData.items[i], c)) return false;
        return true;
    }
    if (isNumber(raw) && isNumber(noData)) {
        if (c == ComponentType::Float32) return float(raw.asNumber()) == float(noData.asNumber());
        if (raw.kind != Kind::Number && noData.kind != Kind::Number) return raw == noData;
        return raw.asNumber() == noData.asNumber();
    }
    return raw == noData;
}

PropertyValue named(const EnumDef* e, const PropertyValue& raw) {
    if (raw.kind == PropertyValue::Kind::Array) {
        std::vector<PropertyValue> items;
        items.reserve(raw.items.size());
        for (const PropertyValue& item : raw.items) items.push_back(named(e, item));
        return PropertyValue::ofArray(std::move(items));
    }
    const std::string* name = e && isNumber(raw) ? e->nameOf(enumRaw(raw)) : nullptr;
    return name ? PropertyValue::ofString(*name) : PropertyValue();
}

// The part of an offset or scale that applies to item i of an array value (the whole of it for a scalar one).
const PropertyValue& itemOf(const PropertyValue& v, size_t i) {
    static const PropertyValue none;
    if (v.kind != PropertyValue::Kind::Array) return v;
    return i < v.items.size() ? v.items[i] : none;
}

PropertyValue transformed(const PropertyValue& v, bool normalized, ComponentType c, const PropertyValue& offset,
                          const PropertyValue& scale) {
    if (v.kind == PropertyValue::Kind::Array) {
        std::vector<PropertyValue> items;
        items.reserve(v.items.size());
        for (size_t i = 0; i < v.items.size(); ++i)
            items.push_back(transformed(v.items[i], normalized, c, itemOf(offset, i), itemOf(scale, i)));
        return PropertyValue::ofArray(std::move(items));
    }
    if (!isNumber(v)) return v;
    double x = v.asNumber();
    if (normalized && isInteger(c)) {
        x /= integerMax(c);
        if (isSigned(c)) x = std::max(x, -1.0);  // INT8 -128 is -1, as is -127
    }
    const double s = isNumber(scale) ? scale.asNumber() : 1.0;
    const double o = isNumber(offset) ? offset.asNumber() : 0.0;
    return PropertyValue::ofNumber(o + s * x);
}

}  // namespace

ComponentType storedType(const Schema& schema, const ClassProperty& p) {
    if (p.type != PropertyType::Enum) return p.componentType;
    if (p.enumIndex < 0 || size_t(p.enumIndex) >= schema.enums.size()) return ComponentType::None;
    return schema.enums[size_t(p.enumIndex)].valueType;
}

bool isInteger(ComponentType c) {
    return c != ComponentType::None && c != ComponentType::Float32 && c != ComponentType::Float64;
}

size_t elementBytes(const Schema& schema, const ClassProperty& p) {
    if (p.type == PropertyType::String || p.type == PropertyType::Boolean) return 0;
    return size_t(componentCount(p.type)) * size_t(componentBytes(storedType(schema, p)));
}

PropertyValue readComponent(ComponentType c, const uint8_t* at) {
    switch (c) {
        case ComponentType::Int8: return PropertyValue::ofInt(load<int8_t>(at));
        case ComponentType::UInt8: return PropertyValue::ofUInt(load<uint8_t>(at));
        case ComponentType::Int16: return PropertyValue::ofInt(load<int16_t>(at));
        case ComponentType::UInt16: return PropertyValue::ofUInt(load<uint16_t>(at));
        case ComponentType::Int32: return PropertyValue::ofInt(load<int32_t>(at));
        case ComponentType::UInt32: return PropertyValue::ofUInt(load<uint32_t>(at));
        case ComponentType::Int64: return PropertyValue::ofInt(load<int64_t>(at));
        case ComponentType::UInt64: return PropertyValue::ofUInt(load<uint64_t>(at));
        case ComponentType::Float32: return PropertyValue::ofNumber(load<float>(at));
        case ComponentType::Float64: return PropertyValue::ofNumber(load<double>(at));
        case ComponentType::None: break;
    }
    return {};
}

uint64_t readOffset(ComponentType c, const uint8_t* at) {
    switch (c) {
        case ComponentType::UInt8: return load<uint8_t>(at);
        case ComponentType::UInt16: return load<uint16_t>(at);
        case ComponentType::UInt32: return load<uint32_t>(at);
        case ComponentType::UInt64: return load<uint64_t>(at);
        default: return 0;
    }
}

PropertyValue readElement(const Schema& schema, const ClassProperty& p, const uint8_t* at) {
    const ComponentType c = storedType(schema, p);
    const int n = componentCount(p.type);
    if (p.type == PropertyType::Scalar || p.type == PropertyType::Enum) return readComponent(c, at);
    std::vector<PropertyValue> items;
    items.reserve(size_t(n));
    for (int i = 0; i < n; ++i) items.push_back(readComponent(c, at + size_t(i) * size_t(componentBytes(c))));
    return PropertyValue::ofArray(std::move(items));
}

int64_t enumRaw(const PropertyValue& raw) {
    // A UINT64 enum value past INT64_MAX wraps, as the schema reader stores it.
    return raw.kind == PropertyValue::Kind::Unsigned ? int64_t(raw.unsignedInteger) : int64_t(raw.asNumber());
}

PropertyValue finish(const Schema& schema, const ClassProperty& p, PropertyValue raw, const PropertyOverrides& o) {
    if (p.type == PropertyType::Enum) {
        const bool known = p.enumIndex >= 0 && size_t(p.enumIndex) < schema.enums.size();
        raw = named(known ? &schema.enums[size_t(p.enumIndex)] : nullptr, raw);  // noData names an enum value too
    }
    const ComponentType c = storedType(schema, p);
    if (!p.noData.isNull() && isNoData(raw, p.noData, c)) return p.defaultValue;
    switch (p.type) {
        case PropertyType::String:
        case PropertyType::Boolean:
        case PropertyType::Enum: return raw;
        default: break;
    }
    const PropertyValue& offset = o.offset.isNull() ? p.offset : o.offset;
    const PropertyValue& scale = o.scale.isNull() ? p.scale : o.scale;
    // Integers stay exact (INT64 past 2^53 included) unless a transform makes them real numbers.
    if (!p.normalized && offset.isNull() && scale.isNull()) return raw;
    return transformed(raw, p.normalized, c, offset, scale);
}

}  // namespace sg::props
