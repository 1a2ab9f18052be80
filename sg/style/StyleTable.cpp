#include "sg/style/StyleTable.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace sg {

namespace {

std::optional<StyleValue::Kind> kindOf(const ClassProperty& p) {
    using K = StyleValue::Kind;
    if (p.array) return std::nullopt;
    switch (p.type) {
        case PropertyType::Scalar: return K::Number;
        case PropertyType::Vec2: return K::Vec2;
        case PropertyType::Vec3: return K::Vec3;
        case PropertyType::Vec4: return K::Vec4;
        case PropertyType::String:
        case PropertyType::Enum: return K::String;
        case PropertyType::Boolean: return K::Boolean;
        default: return std::nullopt;  // matrices
    }
}

const ClassDef& classOf(const PropertyStore& store, int table) {
    if (table < 0 || size_t(table) >= store.tables().size())
        throw std::out_of_range("styleTable(): no property table " + std::to_string(table));
    const int c = store.tables()[size_t(table)].classIndex;
    if (c < 0 || size_t(c) >= store.schema.classes.size())
        throw std::out_of_range("styleTable(): table " + std::to_string(table) + " has no class");
    return store.schema.classes[size_t(c)];
}

// One row at a time; a property read once per row however often the style reads it.
class TableRow final : public StyleFeature {
public:
    TableRow(const PropertyStore& store, int table, size_t properties)
        : store_(store), table_(table), values_(properties), readAt_(properties, 0) {}
    void setRow(uint64_t row) { row_ = row; }
    const PropertyValue* property(int slot) const override {
        if (slot < 0 || size_t(slot) >= values_.size()) return nullptr;
        if (readAt_[size_t(slot)] != row_ + 1) {
            values_[size_t(slot)] = store_.value(table_, row_, slot);
            readAt_[size_t(slot)] = row_ + 1;
        }
        return &values_[size_t(slot)];
    }

private:
    const PropertyStore& store_;
    int table_;
    uint64_t row_ = 0;
    mutable std::vector<PropertyValue> values_;
    mutable std::vector<uint64_t> readAt_;  // row + 1 of the value held; 0: none
};

uint8_t byte(float c) { return uint8_t(std::lround(c * 255.0f)); }  // c in 0..1

}  // namespace

StyleBinder propertyTableBinder(const PropertyStore& store, int table) {
    const ClassDef* c = &classOf(store, table);
    return [c](const std::string& name) {
        StyleBinding b;
        b.slot = c->find(name);
        if (b.slot >= 0) b.kind = kindOf(c->properties[size_t(b.slot)]);
        return b;
    };
}

StyledTable styleTable(const Style& style, const PropertyStore& store, int table) {
    Style bound = style;
    bound.bind(propertyTableBinder(store, table));
    const uint64_t count = store.tables()[size_t(table)].count;
    if (count > SIZE_MAX / 8) throw std::length_error("styleTable(): " + std::to_string(count) + " rows");
    TableRow row(store, table, classOf(store, table).properties.size());
    StyledTable out;
    out.rgba.resize(size_t(count) * 4);
    std::vector<float> sizes(size_t(count), 1.0f);
    bool anySize = false;
    for (uint64_t r = 0; r < count; ++r) {
        row.setRow(r);
        const StyleLook look = bound.evaluate(row);
        uint8_t* px = &out.rgba[size_t(r) * 4];
        for (int i = 0; i < 4; ++i) px[i] = look.show ? byte(look.color[size_t(i)]) : 0;
        if (!look.show) continue;
        sizes[size_t(r)] = look.pointSize;
        anySize = anySize || look.pointSize != 1.0f;
    }
    if (anySize) out.pointSizes = std::move(sizes);
    return out;
}

}  // namespace sg
