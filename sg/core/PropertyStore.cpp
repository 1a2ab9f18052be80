// The property store (sg/core/Properties.h): tables checked whole when added, so that a read needs no check of its
// own and never fails; values read from the bytes on demand.
#include "sg/core/internal/PropertyDecode.h"

#include <stdexcept>

namespace sg {

using props::elementBytes;
using props::readOffset;

namespace {

// A column's elements: [first, last) of the values (for a variable-length array, as its array offsets bound them).
struct ElementRange {
    uint64_t first = 0, last = 0;
};

bool isOffsetType(ComponentType c) {
    return c == ComponentType::UInt8 || c == ComponentType::UInt16 || c == ComponentType::UInt32 ||
           c == ComponentType::UInt64;
}

// Checks one column of a table being added; every failure throws std::invalid_argument naming the property.
class ColumnCheck {
public:
    ColumnCheck(const std::vector<std::vector<uint8_t>>& buffers, const Schema& schema, const PropertyTable& table,
                const PropertyColumn& column, const ClassProperty& p)
        : buffers_(buffers), schema_(schema), table_(table), column_(column), p_(p) {}

    void run() {
        span(column_.values, "values");
        if (!column_.values.present()) fail("no values");
        const ElementRange r = elements();
        const uint64_t size = column_.values.size;
        if (p_.type == PropertyType::String) {
            if (r.last == UINT64_MAX) fail("stringOffsets too short");
            offsets(column_.stringOffsets, column_.stringOffsetType, r.last + 1, size, "stringOffsets");
        } else if (p_.type == PropertyType::Boolean) {
            if (r.last / 8 + (r.last % 8 ? 1 : 0) > size) fail(tooShort(r.last, "bits"));
        } else {
            const size_t bytes = elementBytes(schema_, p_);
            if (bytes == 0) fail("no component type");
            if (r.last > size / bytes) fail(tooShort(r.last, "elements of " + std::to_string(bytes) + " bytes"));
            if (p_.type == PropertyType::Enum) enumValues(r, bytes);
        }
    }

private:
    [[noreturn]] void fail(const std::string& reason) const {
        throw std::invalid_argument("PropertyStore::addTable(): table '" + table_.name + "', property '" + p_.id +
                                    "': " + reason);
    }

    std::string tooShort(uint64_t n, const std::string& what) const {
        return "values too short for " + std::to_string(table_.count) + " rows (" + std::to_string(n) + " " + what +
               ", " + std::to_string(column_.values.size) + " bytes given)";
    }

    void span(const ByteSpan& s, const char* what) const {
        if (!s.present()) return;
        if (size_t(s.buffer) >= buffers_.size()) fail(std::string(what) + ": no buffer " + std::to_string(s.buffer));
        const uint64_t size = buffers_[size_t(s.buffer)].size();
        if (s.offset > size || s.size > size - s.offset)
            fail(std::string(what) + ": bytes " + std::to_string(s.offset) + " + " + std::to_string(s.size) +
                 " past the buffer's " + std::to_string(size));
    }

    const uint8_t* data(const ByteSpan& s) const { return buffers_[size_t(s.buffer)].data() + s.offset; }

    // Checks `entries` offsets of type `type`: present, inside their span, ascending, the last at most `limit`.
    // Returns the first and the last.
    ElementRange offsets(const ByteSpan& s, ComponentType type, uint64_t entries, uint64_t limit, const char* what) {
        span(s, what);
        if (!s.present()) fail(std::string("no ") + what);
        if (!isOffsetType(type)) fail(std::string(what) + ": offset type " + componentTypeName(type));
        const size_t bytes = size_t(componentBytes(type));
        if (entries > s.size / bytes)
            fail(std::string(what) + " too short: " + std::to_string(entries) + " offsets of " + std::to_string(bytes) +
                 " bytes, " + std::to_string(s.size) + " bytes given");
        const uint8_t* at = data(s);
        ElementRange r{readOffset(type, at), 0};
        uint64_t previous = r.first;
        for (uint64_t i = 1; i < entries; ++i) {
            const uint64_t o = readOffset(type, at + i * bytes);
            if (o < previous)
                fail(std::string(what) + " not ascending at " + std::to_string(i) + " (" + std::to_string(o) +
                     " after " + std::to_string(previous) + ")");
            previous = o;
        }
        r.last = previous;
        if (r.last > limit)
            fail(std::string(what) + ": last offset " + std::to_string(r.last) + " past the " + std::to_string(limit) +
                 " the values hold");
        return r;
    }

    ElementRange elements() {
        if (p_.array && p_.count == 0) {
            if (table_.count == UINT64_MAX) fail("arrayOffsets too short");
            // Element indices (of string offsets, for strings; of bits, for booleans): bounded by the checks after.
            return offsets(column_.arrayOffsets, column_.arrayOffsetType, table_.count + 1, UINT64_MAX, "arrayOffsets");
        }
        const uint64_t perRow = p_.array ? p_.count : 1;
        if (table_.count > UINT64_MAX / perRow) fail("count times array count overflows");
        return {0, table_.count * perRow};
    }

    // Every enum value present has a name: reads then never meet an unnamed one.
    void enumValues(const ElementRange& r, size_t bytes) const {
        const auto& e = schema_.enums[size_t(p_.enumIndex)];
        if (!props::isInteger(e.valueType)) fail("enum value type " + std::string(componentTypeName(e.valueType)));
        const uint8_t* at = data(column_.values);
        for (uint64_t i = r.first; i < r.last; ++i) {
            const int64_t v = props::enumRaw(props::readComponent(e.valueType, at + i * bytes));
            if (!e.nameOf(v))
                fail("value " + std::to_string(v) + " of row element " + std::to_string(i) + " is not in enum '" +
                     e.id + "'");
        }
    }

    const std::vector<std::vector<uint8_t>>& buffers_;
    const Schema& schema_;
    const PropertyTable& table_;
    const PropertyColumn& column_;
    const ClassProperty& p_;
};

}  // namespace

int PropertyStore::addBuffer(std::vector<uint8_t> bytes) {
    buffers_.push_back(std::move(bytes));
    return int(buffers_.size() - 1);
}

int PropertyStore::addTable(PropertyTable table) {
    const std::string prefix = "PropertyStore::addTable(): table '" + table.name + "'";
    if (table.classIndex < 0 || size_t(table.classIndex) >= schema.classes.size())
        throw std::invalid_argument(prefix + ": no class " + std::to_string(table.classIndex));
    const ClassDef& cls = schema.classes[size_t(table.classIndex)];
    std::vector<bool> seen(cls.properties.size(), false);
    for (const PropertyColumn& column : table.columns) {
        if (column.property < 0 || size_t(column.property) >= cls.properties.size())
            throw std::invalid_argument(prefix + ", property " + std::to_string(column.property) +
                                        ": no such property in class '" + cls.id + "'");
        const ClassProperty& p = cls.properties[size_t(column.property)];
        if (seen[size_t(column.property)])
            throw std::invalid_argument(prefix + ", property '" + p.id + "': two columns");
        seen[size_t(column.property)] = true;
        if (p.type == PropertyType::Enum && (p.enumIndex < 0 || size_t(p.enumIndex) >= schema.enums.size()))
            throw std::invalid_argument(prefix + ", property '" + p.id + "': no enum " + std::to_string(p.enumIndex));
        ColumnCheck(buffers_, schema, table, column, p).run();
    }
    tables_.push_back(std::move(table));
    return int(tables_.size() - 1);
}

namespace {

// One element k of a checked column: a string, a bit, or a fixed-size element.
PropertyValue readOne(const Schema& schema, const ClassProperty& p, const PropertyColumn& col, const uint8_t* values,
                      const uint8_t* stringOffsets, uint64_t k) {
    if (p.type == PropertyType::String) {
        const size_t b = size_t(componentBytes(col.stringOffsetType));
        const uint64_t start = readOffset(col.stringOffsetType, stringOffsets + k * b);
        const uint64_t end = readOffset(col.stringOffsetType, stringOffsets + (k + 1) * b);
        return PropertyValue::ofString(std::string(reinterpret_cast<const char*>(values + start), end - start));
    }
    if (p.type == PropertyType::Boolean) return PropertyValue::ofBool((values[k / 8] >> (k % 8)) & 1);
    return props::readElement(schema, p, values + k * elementBytes(schema, p));
}

}  // namespace

PropertyValue PropertyStore::value(int t, uint64_t rowIndex, int property) const {
    if (t < 0 || size_t(t) >= tables_.size())
        throw std::out_of_range("PropertyStore::value(): no table " + std::to_string(t));
    const PropertyTable& table = tables_[size_t(t)];
    const ClassDef& cls = schema.classes[size_t(table.classIndex)];
    if (property < 0 || size_t(property) >= cls.properties.size())
        throw std::out_of_range("PropertyStore::value(): no property " + std::to_string(property) + " in class '" +
                                cls.id + "'");
    const ClassProperty& p = cls.properties[size_t(property)];
    if (rowIndex >= table.count) return {};
    const PropertyColumn* col = table.column(property);
    if (!col) return p.defaultValue;

    auto bytesOf = [&](const ByteSpan& s) { return s.present() ? buffer(s.buffer).data() + s.offset : nullptr; };
    const uint8_t* values = bytesOf(col->values);
    const uint8_t* stringOffsets = bytesOf(col->stringOffsets);
    uint64_t first = 0, n = 1;
    if (p.array && p.count == 0) {
        const uint8_t* ao = bytesOf(col->arrayOffsets);
        const size_t b = size_t(componentBytes(col->arrayOffsetType));
        first = readOffset(col->arrayOffsetType, ao + rowIndex * b);
        n = readOffset(col->arrayOffsetType, ao + (rowIndex + 1) * b) - first;
    } else if (p.array) {
        n = p.count;
        first = rowIndex * n;
    } else {
        first = rowIndex;
    }
    if (!p.array)
        return props::finish(schema, p, readOne(schema, p, *col, values, stringOffsets, first), col->overrides);
    std::vector<PropertyValue> items;
    items.reserve(size_t(n));
    for (uint64_t i = 0; i < n; ++i) items.push_back(readOne(schema, p, *col, values, stringOffsets, first + i));
    return props::finish(schema, p, PropertyValue::ofArray(std::move(items)), col->overrides);
}

std::vector<std::pair<std::string, PropertyValue>> PropertyStore::row(int t, uint64_t rowIndex) const {
    if (t < 0 || size_t(t) >= tables_.size())
        throw std::out_of_range("PropertyStore::row(): no table " + std::to_string(t));
    const ClassDef& cls = schema.classes[size_t(tables_[size_t(t)].classIndex)];
    std::vector<std::pair<std::string, PropertyValue>> out;
    out.reserve(cls.properties.size());
    for (size_t i = 0; i < cls.properties.size(); ++i)
        out.emplace_back(cls.properties[i].id, value(t, rowIndex, int(i)));
    return out;
}

PropertyValue PropertyStore::decode(int classIndex, int property, const uint8_t* bytes, size_t size,
                                    const PropertyOverrides& overrides) const {
    if (classIndex < 0 || size_t(classIndex) >= schema.classes.size())
        throw std::out_of_range("PropertyStore::decode(): no class " + std::to_string(classIndex));
    const ClassDef& cls = schema.classes[size_t(classIndex)];
    if (property < 0 || size_t(property) >= cls.properties.size())
        throw std::out_of_range("PropertyStore::decode(): no property " + std::to_string(property) + " in class '" +
                                cls.id + "'");
    const ClassProperty& p = cls.properties[size_t(property)];
    // Textures and attributes hold fixed-size elements only: no strings, no variable-length arrays.
    if (p.type == PropertyType::String || (p.array && p.count == 0) || (!bytes && size)) return {};
    const uint64_t n = p.array ? p.count : 1;
    std::vector<PropertyValue> items;
    if (p.type == PropertyType::Boolean) {
        if (n > uint64_t(size) * 8) return {};
        for (uint64_t k = 0; k < n; ++k) items.push_back(PropertyValue::ofBool((bytes[k / 8] >> (k % 8)) & 1));
    } else {
        const size_t eb = elementBytes(schema, p);
        if (eb == 0 || n > size / eb) return {};
        for (uint64_t k = 0; k < n; ++k) items.push_back(props::readElement(schema, p, bytes + k * eb));
    }
    PropertyValue raw = p.array ? PropertyValue::ofArray(std::move(items)) : std::move(items[0]);
    return props::finish(schema, p, std::move(raw), overrides);
}

size_t PropertyStore::bytes() const {
    size_t n = sizeof(*this);
    for (const auto& b : buffers_) n += sizeof(b) + b.capacity();
    for (const PropertyTable& t : tables_)
        n += sizeof(t) + t.name.capacity() + t.columns.capacity() * sizeof(PropertyColumn);
    return n;
}

PropertyValue propertyValueOf(const Schema& schema, const ClassProperty& p, PropertyValue raw,
                              const PropertyOverrides& overrides) {
    return props::finish(schema, p, std::move(raw), overrides);
}

}  // namespace sg
