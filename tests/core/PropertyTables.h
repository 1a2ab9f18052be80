// Property tables made byte by byte for the property store's tests: one property, its class and its column.
#pragma once
#include "sg/core/Properties.h"

#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

namespace sg::test {

// Values as the files store them, little-endian (the test hosts are little-endian too, so memcpy gives that order).
template <typename T>
std::vector<uint8_t> le(std::initializer_list<T> values) {
    std::vector<uint8_t> out;
    for (const T& v : values) {
        uint8_t raw[sizeof(T)];
        std::memcpy(raw, &v, sizeof(T));
        out.insert(out.end(), raw, raw + sizeof(T));
    }
    return out;
}

inline std::vector<uint8_t> textBytes(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }

inline ClassProperty prop(const std::string& id, PropertyType type, ComponentType component = ComponentType::None) {
    ClassProperty p;
    p.id = id;
    p.type = type;
    p.componentType = component;
    return p;
}

// A column's bytes: values always present (possibly empty), the offsets when not empty.
struct ColumnBytes {
    ColumnBytes(std::vector<uint8_t> v, std::vector<uint8_t> ao = {}, std::vector<uint8_t> so = {})
        : values(std::move(v)), arrayOffsets(std::move(ao)), stringOffsets(std::move(so)) {}
    std::vector<uint8_t> values, arrayOffsets, stringOffsets;
    ComponentType arrayOffsetType = ComponentType::UInt32, stringOffsetType = ComponentType::UInt32;
    PropertyOverrides overrides;
};

// A table of `count` rows of one column of property `p`, in a class of its own (property 0) added to the store's
// schema, over buffers added to the store. The table is returned, not added.
inline PropertyTable oneColumn(PropertyStore& store, const ClassProperty& p, uint64_t count, ColumnBytes c) {
    ClassDef cls;
    cls.id = "class" + std::to_string(store.schema.classes.size());
    cls.properties.push_back(p);
    store.schema.classes.push_back(cls);
    auto span = [&](std::vector<uint8_t> bytes, bool always) {
        ByteSpan s;
        if (bytes.empty() && !always) return s;
        s.size = bytes.size();
        s.buffer = store.addBuffer(std::move(bytes));
        return s;
    };
    PropertyColumn col;
    col.property = 0;
    col.values = span(std::move(c.values), true);
    col.arrayOffsets = span(std::move(c.arrayOffsets), false);
    col.stringOffsets = span(std::move(c.stringOffsets), false);
    col.arrayOffsetType = c.arrayOffsetType;
    col.stringOffsetType = c.stringOffsetType;
    col.overrides = c.overrides;
    PropertyTable t;
    t.name = "table";
    t.classIndex = int(store.schema.classes.size() - 1);
    t.count = count;
    t.columns.push_back(col);
    return t;
}

inline PropertyValue ints(std::initializer_list<int64_t> v) {
    std::vector<PropertyValue> items;
    for (int64_t i : v) items.push_back(PropertyValue::ofInt(i));
    return PropertyValue::ofArray(items);
}

inline PropertyValue numbers(std::initializer_list<double> v) {
    std::vector<PropertyValue> items;
    for (double d : v) items.push_back(PropertyValue::ofNumber(d));
    return PropertyValue::ofArray(items);
}

}  // namespace sg::test
