#include "sg/core/PropertyTableBuilder.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace sg {
namespace {

// Little-endian whatever the host: the files' byte order.
void putLE(std::vector<uint8_t>& out, uint64_t bits, int bytes) {
    for (int b = 0; b < bytes; ++b) out.push_back(uint8_t(bits >> (8 * b)));
}

bool isFloat(ComponentType c) { return c == ComponentType::Float32 || c == ComponentType::Float64; }
bool isSigned(ComponentType c) {
    return c == ComponentType::Int8 || c == ComponentType::Int16 || c == ComponentType::Int32 ||
           c == ComponentType::Int64;
}
bool isNumber(const PropertyValue& v) {
    return v.kind == PropertyValue::Kind::Integer || v.kind == PropertyValue::Kind::Unsigned ||
           v.kind == PropertyValue::Kind::Number;
}

// Whether an integer value fits component type `c` exactly (a Number must be integral).
bool fitsInteger(const PropertyValue& v, ComponentType c) {
    const int bits = 8 * componentBytes(c);
    if (v.kind == PropertyValue::Kind::Number) {
        if (v.number != std::floor(v.number)) return false;
        const double lo = isSigned(c) ? -std::ldexp(1.0, bits - 1) : 0.0;
        const double hi = isSigned(c) ? std::ldexp(1.0, bits - 1) : std::ldexp(1.0, bits);
        return v.number >= lo && v.number < hi;
    }
    if (v.kind == PropertyValue::Kind::Unsigned) {
        const uint64_t hi = isSigned(c)  ? (uint64_t(1) << (bits - 1)) - 1
                            : bits == 64 ? UINT64_MAX
                                         : (uint64_t(1) << bits) - 1;
        return v.unsignedInteger <= hi;
    }
    if (!isSigned(c)) return v.integer >= 0 && (bits == 64 || uint64_t(v.integer) < (uint64_t(1) << bits));
    if (bits == 64) return true;
    return v.integer >= -(int64_t(1) << (bits - 1)) && v.integer < (int64_t(1) << (bits - 1));
}

// An integer value's two's-complement bits (checked by fitsInteger first).
uint64_t integerBits(const PropertyValue& v) {
    if (v.kind == PropertyValue::Kind::Unsigned) return v.unsignedInteger;
    if (v.kind == PropertyValue::Kind::Integer) return uint64_t(v.integer);
    return v.number < 0 ? uint64_t(int64_t(v.number)) : uint64_t(v.number);
}

int enumValue(const std::vector<std::string>& names, const std::string& name) {
    for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return int(i);
    return -1;
}

}  // namespace

PropertyTableBuilder::PropertyTableBuilder(std::string classId, std::string tableName)
    : classId_(std::move(classId)), tableName_(std::move(tableName)) {}

int PropertyTableBuilder::add(Column c) {
    if (rows_ > 0) throw std::invalid_argument("PropertyTableBuilder: column '" + c.property.id + "' added after rows");
    for (const Column& o : columns_)
        if (o.property.id == c.property.id)
            throw std::invalid_argument("PropertyTableBuilder: column '" + c.property.id + "' added twice");
    if (c.property.type == PropertyType::String) c.stringOffsets.push_back(0);
    columns_.push_back(std::move(c));
    return int(columns_.size()) - 1;
}

int PropertyTableBuilder::addScalar(std::string id, ComponentType type) {
    if (type == ComponentType::None)
        throw std::invalid_argument("PropertyTableBuilder::addScalar(): column '" + id + "' has no component type");
    Column c;
    c.property.id = std::move(id);
    c.property.type = PropertyType::Scalar;
    c.property.componentType = type;
    return add(std::move(c));
}

int PropertyTableBuilder::addString(std::string id) {
    Column c;
    c.property.id = std::move(id);
    c.property.type = PropertyType::String;
    return add(std::move(c));
}

int PropertyTableBuilder::addBoolean(std::string id) {
    Column c;
    c.property.id = std::move(id);
    c.property.type = PropertyType::Boolean;
    return add(std::move(c));
}

int PropertyTableBuilder::addEnum(std::string id, std::string enumId, const std::vector<std::string>& names) {
    if (names.empty() || names.size() > 65536)
        throw std::invalid_argument("PropertyTableBuilder::addEnum(): enum '" + enumId + "' needs 1 to 65536 names");
    Column c;
    c.property.id = std::move(id);
    c.property.type = PropertyType::Enum;
    c.enumId = std::move(enumId);
    c.enumNames = names;
    return add(std::move(c));
}

std::string PropertyTableBuilder::check(const Column& c, const PropertyValue& v) const {
    switch (c.property.type) {
        case PropertyType::String:
            if (v.kind != PropertyValue::Kind::String) return "not a string";
            if (c.stringOffsets.back() + uint64_t(v.string.size()) > UINT32_MAX)
                return "strings longer than 4 GiB in all";
            return {};
        case PropertyType::Boolean: return v.kind == PropertyValue::Kind::Boolean ? "" : "not a boolean";
        case PropertyType::Enum:
            if (v.kind != PropertyValue::Kind::String || enumValue(c.enumNames, v.string) < 0)
                return "not a name of enum '" + c.enumId + "'";
            return {};
        default:
            if (!isNumber(v)) return "not a number";
            if (!isFloat(c.property.componentType) && !fitsInteger(v, c.property.componentType))
                return v.toString() + " does not fit " + componentTypeName(c.property.componentType);
            return {};
    }
}

void PropertyTableBuilder::append(Column& c, const PropertyValue& v) const {
    switch (c.property.type) {
        case PropertyType::String:
            c.values.insert(c.values.end(), v.string.begin(), v.string.end());
            c.stringOffsets.push_back(uint32_t(c.values.size()));
            return;
        case PropertyType::Boolean:
            if (rows_ % 8 == 0) c.values.push_back(0);
            if (v.boolean) c.values.back() |= uint8_t(1u << (rows_ % 8));
            return;
        case PropertyType::Enum: putLE(c.values, uint64_t(enumValue(c.enumNames, v.string)), 2); return;
        default: break;
    }
    const ComponentType t = c.property.componentType;
    if (t == ComponentType::Float32) {
        const float f = float(v.asNumber());
        uint32_t bits;
        std::memcpy(&bits, &f, 4);
        putLE(c.values, bits, 4);
    } else if (t == ComponentType::Float64) {
        const double d = v.asNumber();
        uint64_t bits;
        std::memcpy(&bits, &d, 8);
        putLE(c.values, bits, 8);
    } else {
        putLE(c.values, integerBits(v), componentBytes(t));
    }
}

void PropertyTableBuilder::addRow(const std::vector<PropertyValue>& values) {
    if (values.size() != columns_.size())
        throw std::invalid_argument("PropertyTableBuilder::addRow(): " + std::to_string(values.size()) +
                                    " values for " + std::to_string(columns_.size()) + " columns");
    for (size_t i = 0; i < values.size(); ++i) {
        const std::string reason = check(columns_[i], values[i]);
        if (!reason.empty())
            throw std::invalid_argument("PropertyTableBuilder::addRow(): column '" + columns_[i].property.id +
                                        "' of row " + std::to_string(rows_) + ": " + reason);
    }
    for (size_t i = 0; i < values.size(); ++i) append(columns_[i], values[i]);
    ++rows_;
}

std::vector<uint8_t> PropertyTableBuilder::bytes() const {
    std::vector<uint8_t> out;
    const auto align = [&] { out.resize((out.size() + 7) / 8 * 8, 0); };
    for (const Column& c : columns_) {
        align();
        out.insert(out.end(), c.values.begin(), c.values.end());
        if (c.property.type != PropertyType::String) continue;
        align();
        for (uint32_t o : c.stringOffsets) putLE(out, o, 4);
    }
    return out;
}

int PropertyTableBuilder::finish(PropertyStore& store) const {
    if (store.schema.findClass(classId_) >= 0)
        throw std::invalid_argument("PropertyTableBuilder::finish(): the store has a class '" + classId_ + "'");
    Schema& schema = store.schema;
    const size_t enumsBefore = schema.enums.size();
    ClassDef cls;
    cls.id = classId_;
    PropertyTable table;
    table.name = tableName_;
    table.count = rows_;
    uint64_t at = 0;
    for (size_t i = 0; i < columns_.size(); ++i) {
        const Column& c = columns_[i];
        ClassProperty p = c.property;
        if (p.type == PropertyType::Enum) {
            if (schema.findEnum(c.enumId) >= 0) {
                schema.enums.resize(enumsBefore);
                throw std::invalid_argument("PropertyTableBuilder::finish(): the store has an enum '" + c.enumId + "'");
            }
            EnumDef e;
            e.id = c.enumId;
            e.valueType = ComponentType::UInt16;
            for (size_t v = 0; v < c.enumNames.size(); ++v) e.values.emplace_back(c.enumNames[v], int64_t(v));
            p.enumIndex = int(schema.enums.size());
            schema.enums.push_back(std::move(e));
        }
        cls.properties.push_back(std::move(p));
        PropertyColumn col;
        col.property = int(i);
        at = (at + 7) / 8 * 8;
        col.values = ByteSpan{0, at, uint64_t(c.values.size())};
        at += c.values.size();
        if (c.property.type == PropertyType::String) {
            at = (at + 7) / 8 * 8;
            col.stringOffsets = ByteSpan{0, at, uint64_t(c.stringOffsets.size()) * 4};
            col.stringOffsetType = ComponentType::UInt32;
            at += c.stringOffsets.size() * 4;
        }
        table.columns.push_back(col);
    }
    table.classIndex = int(schema.classes.size());
    schema.classes.push_back(std::move(cls));
    const int buffer = store.addBuffer(bytes());
    for (PropertyColumn& col : table.columns) {
        col.values.buffer = buffer;
        if (col.stringOffsets.size > 0) col.stringOffsets.buffer = buffer;
    }
    try {
        return store.addTable(std::move(table));
    } catch (...) {
        // The schema as it was; the buffer stays, unread.
        schema.classes.pop_back();
        schema.enums.resize(enumsBefore);
        throw;
    }
}

ref_ptr<MeshFeatures> rowFeatures(ref_ptr<const PropertyStore> store, int table, std::string label) {
    if (!store || table < 0 || size_t(table) >= store->tables().size())
        throw std::invalid_argument("rowFeatures(): no table " + std::to_string(table) + " in the store");
    const uint64_t rows = store->tables()[size_t(table)].count;
    if (rows > UINT32_MAX) throw std::invalid_argument("rowFeatures(): more than 2^32 rows");
    auto f = make<MeshFeatures>();
    FeatureIdSet set;
    set.source = FeatureIdSet::Source::Instance;
    set.label = std::move(label);
    set.featureCount = uint32_t(rows);
    set.propertyTable = table;
    set.ids.resize(size_t(rows));
    for (uint32_t i = 0; i < uint32_t(rows); ++i) set.ids[i] = i;
    f->sets.push_back(std::move(set));
    f->store = std::move(store);
    return f;
}

}  // namespace sg
