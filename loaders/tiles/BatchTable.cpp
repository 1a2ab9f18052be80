// A batch table into the property store. Each JSON array becomes the narrowest column that holds its values:
// booleans a BOOLEAN bitstream; integers INT64; other numbers FLOAT64; strings a STRING (offsets and bytes);
// arrays of N numbers VECN FLOAT64 (N 2..4) or a fixed-length FLOAT64 array (other N). Anything else (objects,
// mixed kinds, arrays of varying length, booleans with gaps) is kept as a STRING of each value's JSON text, so
// that nothing in the file is lost. A value that is missing (a JSON null) reads as Null through the column's
// noData. Binary properties are columns over the binary body, read in place.
#include "loaders/tiles/internal/BatchTable.h"

#include "loaders/gltf/internal/GltfDetail.h"  // checkJsonDepth, fail

#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

namespace sg::tiles {
namespace batch {
namespace {

using gltf::fail;
using json = nlohmann::ordered_json;  // objects keep their members in the file's order (a schema's properties)

// The encoded columns may take this much: a hierarchy repeats an ancestor's values for every feature.
constexpr uint64_t kMaxEncodedBytes = uint64_t(256) << 20;

template <class T>
void put(std::vector<uint8_t>& out, T v) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // the supported hosts are little-endian, as the format is
    out.insert(out.end(), b, b + sizeof(T));
}

bool missing(const json* v) { return !v || v->is_null(); }

bool isInt64(const json& v) {
    return v.is_number_integer() &&
           !(v.is_number_unsigned() && v.get<uint64_t>() > uint64_t(std::numeric_limits<int64_t>::max()));
}

// What kind of column the values make.
enum class Shape { Boolean, Integer, Number, String, Vector, Text };

struct Survey {
    Shape shape = Shape::Text;
    bool gaps = false;  // some values missing
    size_t length = 0;  // Vector: the arrays' length
    bool emptyString = false;
};

Survey survey(const std::vector<const json*>& values) {
    Survey s;
    bool any = false, boolean = true, integer = true, number = true, string = true, vector = true;
    for (const json* v : values) {
        if (missing(v)) {
            s.gaps = true;
            continue;
        }
        const bool first = !any;
        any = true;
        boolean = boolean && v->is_boolean();
        integer = integer && isInt64(*v);
        number = number && v->is_number();
        string = string && v->is_string();
        if (v->is_string() && v->get_ref<const std::string&>().empty()) s.emptyString = true;
        if (vector) {
            vector = v->is_array() && !v->empty() && (first || v->size() == s.length);
            for (size_t k = 0; vector && k < v->size(); ++k) vector = (*v)[k].is_number();
            s.length = v->size();
        }
    }
    if (!any) return s;  // all missing: Text, every row Null
    if (boolean && !s.gaps)
        s.shape = Shape::Boolean;  // BOOLEAN has no noData: gaps go to Text
    else if (integer)
        s.shape = Shape::Integer;
    else if (number)
        s.shape = Shape::Number;
    else if (string && !(s.gaps && s.emptyString))
        s.shape = Shape::String;  // "" is the noData of gaps
    else if (vector)
        s.shape = Shape::Vector;
    return s;
}

}  // namespace

ComponentType componentOf(const std::string& name) {
    static const std::pair<const char*, ComponentType> names[] = {
        {"BYTE", ComponentType::Int8},     {"UNSIGNED_BYTE", ComponentType::UInt8},
        {"SHORT", ComponentType::Int16},   {"UNSIGNED_SHORT", ComponentType::UInt16},
        {"INT", ComponentType::Int32},     {"UNSIGNED_INT", ComponentType::UInt32},
        {"FLOAT", ComponentType::Float32}, {"DOUBLE", ComponentType::Float64}};
    for (const auto& [n, c] : names)
        if (name == n) return c;
    return ComponentType::None;
}

json jsonElement(const unsigned char* data, ComponentType c, int components, uint64_t i) {
    const size_t size = size_t(componentBytes(c));
    const unsigned char* p = data + size_t(i) * size * size_t(components);
    auto one = [&](int k) -> json {
        const unsigned char* q = p + size_t(k) * size;
        switch (c) {
            case ComponentType::Int8: return int8_t(q[0]);
            case ComponentType::UInt8: return q[0];
            case ComponentType::Int16: return int16_t(uint16_t(q[0] | q[1] << 8));
            case ComponentType::UInt16: return uint16_t(q[0] | q[1] << 8);
            case ComponentType::Int32:
                return int32_t(uint32_t(q[0]) | uint32_t(q[1]) << 8 | uint32_t(q[2]) << 16 | uint32_t(q[3]) << 24);
            case ComponentType::UInt32:
                return uint32_t(q[0]) | uint32_t(q[1]) << 8 | uint32_t(q[2]) << 16 | uint32_t(q[3]) << 24;
            case ComponentType::Float32: {
                float f;
                std::memcpy(&f, q, 4);
                return f;
            }
            case ComponentType::Float64: {
                double d;
                std::memcpy(&d, q, 8);
                return d;
            }
            default: return nullptr;
        }
    };
    if (components == 1) return one(0);
    json a = json::array();
    for (int k = 0; k < components; ++k) a.push_back(one(k));
    return a;
}

void Columns::reserve(uint64_t bytes, const std::string& path) const {
    if (bytes > kMaxEncodedBytes - encoded.size())
        fail(file, path, "the batch table's values take more than " + std::to_string(kMaxEncodedBytes >> 20) + " MiB");
}

uint64_t Columns::binaryOffset(const json& ref, ComponentType c, int components, uint64_t n,
                               const std::string& path) const {
    const auto off = ref.find("byteOffset");
    if (off == ref.end() || !off->is_number_unsigned())
        fail(file, path + ".byteOffset", "is missing or not a non-negative integer");
    const uint64_t o = off->get<uint64_t>();
    const uint64_t size = uint64_t(componentBytes(c));
    // The spec aligns each binary property to its component size (the body itself starts on 8 bytes).
    if (o % size != 0)
        fail(file, path + ".byteOffset",
             "byteOffset " + std::to_string(o) + " is not a multiple of the component size " + std::to_string(size));
    const uint64_t elem = size * uint64_t(components);
    if (o > binary.size || n > (binary.size - o) / elem)
        fail(file, path + ".byteOffset",
             "byteOffset " + std::to_string(o) + " + " + std::to_string(n) + " elements of " + std::to_string(elem) +
                 " bytes is past the end of the batch table binary (" + std::to_string(binary.size) + " bytes)");
    return o;
}

void Columns::addBinary(const std::string& id, const json& ref, const std::string& path) {
    const auto ct = ref.find("componentType");
    const ComponentType c =
        ct != ref.end() && ct->is_string() ? componentOf(ct->get<std::string>()) : ComponentType::None;
    if (c == ComponentType::None)
        fail(file, path + ".componentType",
             "is missing or unknown (BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT, INT, UNSIGNED_INT, FLOAT, DOUBLE)");
    const auto t = ref.find("type");
    const std::string type = t != ref.end() && t->is_string() ? t->get<std::string>() : "";
    const int components = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 0;
    if (components == 0) fail(file, path + ".type", "is missing or not SCALAR, VEC2, VEC3 or VEC4");
    const uint64_t o = binaryOffset(ref, c, components, count, path);

    ClassProperty p;
    p.id = id;
    p.type = components == 1 ? PropertyType::Scalar : PropertyType(int(PropertyType::Vec2) + components - 2);
    p.componentType = c;
    PropertyColumn col;
    col.property = int(cls.properties.size());
    col.values = ByteSpan{0, o, uint64_t(count) * uint64_t(componentBytes(c)) * uint64_t(components)};
    cls.properties.push_back(std::move(p));
    table.columns.push_back(std::move(col));
}

namespace {

constexpr double kNoNumber = std::numeric_limits<double>::lowest();

// Numbers as INT64 or FLOAT64, or N of them a row (a vector or a fixed-length array); gaps hold the noData.
void encodeNumbers(Columns& c, const std::vector<const json*>& values, const Survey& s, ClassProperty& p,
                   const std::string& path) {
    const uint64_t n = values.size();
    if (s.shape == Shape::Integer) {
        const int64_t noInt = std::numeric_limits<int64_t>::min();
        p.componentType = ComponentType::Int64;
        if (s.gaps) p.noData = PropertyValue::ofInt(noInt);
        c.reserve(8 * n, path);
        for (const json* v : values) put(c.encoded, missing(v) ? noInt : v->get<int64_t>());
        return;
    }
    p.componentType = ComponentType::Float64;
    const size_t k = s.shape == Shape::Vector ? s.length : 1;
    if (k >= 2 && k <= 4) {
        p.type = PropertyType(int(PropertyType::Vec2) + int(k) - 2);
    } else if (k > 1) {
        p.array = true;
        p.count = uint32_t(k);
    }
    if (s.gaps)
        p.noData = k == 1 ? PropertyValue::ofNumber(kNoNumber)
                          : PropertyValue::ofArray(std::vector<PropertyValue>(k, PropertyValue::ofNumber(kNoNumber)));
    c.reserve(8 * n * k, path);
    for (const json* v : values)
        for (size_t i = 0; i < k; ++i)
            put(c.encoded, missing(v) ? kNoNumber : k == 1 ? v->get<double>() : (*v)[i].get<double>());
}

// Strings (or each value's JSON text): the bytes, then the offsets (UINT32 unless they need UINT64).
void encodeStrings(Columns& c, const std::vector<const json*>& values, bool text, ClassProperty& p, PropertyColumn& col,
                   const std::string& path) {
    p.type = PropertyType::String;
    const char* none = text ? "null" : "";
    bool gaps = false;
    const uint64_t start = c.encoded.size();
    std::vector<uint64_t> offsets{0};
    offsets.reserve(values.size() + 1);
    for (const json* v : values) {
        gaps = gaps || missing(v);
        const std::string str = missing(v) ? none : text ? v->dump() : v->get<std::string>();
        c.reserve(str.size(), path);
        c.encoded.insert(c.encoded.end(), str.begin(), str.end());
        offsets.push_back(offsets.back() + str.size());
    }
    if (gaps) p.noData = PropertyValue::ofString(none);
    col.values = ByteSpan{1, start, c.encoded.size() - start};
    const bool wide = offsets.back() > std::numeric_limits<uint32_t>::max();
    col.stringOffsetType = wide ? ComponentType::UInt64 : ComponentType::UInt32;
    while (c.encoded.size() % 8) c.encoded.push_back(0);
    const uint64_t at = c.encoded.size();
    c.reserve(offsets.size() * (wide ? 8 : 4), path);
    for (uint64_t o : offsets) wide ? put(c.encoded, o) : put(c.encoded, uint32_t(o));
    col.stringOffsets = ByteSpan{1, at, c.encoded.size() - at};
}

}  // namespace

void Columns::addJson(const std::string& id, const std::vector<const json*>& values, const std::string& path) {
    const Survey s = survey(values);
    ClassProperty p;
    p.id = id;
    PropertyColumn col;
    col.property = int(cls.properties.size());
    while (encoded.size() % 8) encoded.push_back(0);
    const uint64_t start = encoded.size();
    const uint64_t n = values.size();
    if (s.shape == Shape::Boolean) {  // a bitstream, least significant bit first
        p.type = PropertyType::Boolean;
        reserve((n + 7) / 8, path);
        encoded.resize(size_t(start + (n + 7) / 8), 0);
        for (uint64_t i = 0; i < n; ++i)
            if (values[i]->get<bool>()) encoded[size_t(start + i / 8)] |= uint8_t(1u << (i % 8));
    } else if (s.shape == Shape::String || s.shape == Shape::Text) {
        encodeStrings(*this, values, s.shape == Shape::Text, p, col, path);
    } else {
        encodeNumbers(*this, values, s, p, path);
    }
    if (!col.values.present()) col.values = ByteSpan{1, start, encoded.size() - start};
    cls.properties.push_back(std::move(p));
    table.columns.push_back(std::move(col));
}

}  // namespace batch

namespace {

nlohmann::ordered_json parseJson(const std::string& file, Bytes b) {
    size_t n = b.size;
    while (n > 0 && (b.data[n - 1] == ' ' || b.data[n - 1] == '\0')) --n;  // padding
    if (n == 0) return nlohmann::ordered_json::object();
    nlohmann::ordered_json j;
    try {
        gltf::checkJsonDepth(file, b.data, n);
        j = nlohmann::ordered_json::parse(b.data, b.data + n);
    } catch (const nlohmann::ordered_json::exception& e) {
        gltf::fail(file, "batchTable", std::string("JSON: ") + e.what());
    }
    if (!j.is_object()) gltf::fail(file, "batchTable", "the batch table JSON is not an object");
    return j;
}

// A property of the batch table's JSON: an array of batchLength values or a reference into the binary body.
void addProperty(batch::Columns& c, const std::string& name, const nlohmann::ordered_json& v) {
    const std::string path = "batchTable." + name;
    if (v.is_object()) return c.addBinary(name, v, path);
    if (!v.is_array())
        gltf::fail(c.file, path, "must be an array of batchLength values or a reference to the binary body");
    if (v.size() < c.count)
        gltf::fail(c.file, path,
                   "has " + std::to_string(v.size()) + " values, fewer than batchLength " + std::to_string(c.count));
    if (v.size() > c.count)
        c.warn(path, "has " + std::to_string(v.size()) + " values; those past batchLength " + std::to_string(c.count) +
                         " are left out");
    std::vector<const nlohmann::ordered_json*> values;
    values.reserve(c.count);
    for (uint32_t i = 0; i < c.count; ++i) values.push_back(&v[i]);
    c.addJson(name, values, path);
}

}  // namespace

ref_ptr<PropertyStore> readBatchTable(const std::string& file, Bytes json, Bytes binary, uint32_t batchLength,
                                      std::vector<std::string>& warnings) {
    if (json.size == 0 && binary.size == 0) return nullptr;
    const nlohmann::ordered_json j = parseJson(file, json);
    batch::Columns c{file, binary, batchLength, warnings, {}, {}, {}};
    c.cls.id = kBatchTableClass;
    for (const auto& [name, v] : j.items())
        if (name != "extensions" && name != "extras") addProperty(c, name, v);
    if (const auto ext = j.find("extensions"); ext != j.end() && ext->is_object()) {
        for (const auto& [name, e] : ext->items()) {
            const std::string path = "batchTable.extensions." + name;
            if (name != "3DTILES_batch_table_hierarchy")
                c.warn(path, "extension not read");
            else if (!e.is_object())
                gltf::fail(file, path, "is not an object");
            else
                batch::addHierarchy(c, e, path);
        }
    }

    auto store = make<PropertyStore>();
    store->schema.id = kBatchTableClass;
    store->schema.classes.push_back(std::move(c.cls));
    store->addBuffer(std::vector<uint8_t>(binary.data, binary.data + binary.size));  // 0: read in place
    store->addBuffer(std::move(c.encoded));                                          // 1: made from JSON
    c.table.name = kBatchTableClass;
    c.table.classIndex = 0;
    c.table.count = batchLength;
    try {
        store->addTable(std::move(c.table));
    } catch (const std::invalid_argument& e) {
        gltf::fail(file, "batchTable", e.what());
    }
    return store;
}

}  // namespace sg::tiles
