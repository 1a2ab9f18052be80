// The property store: what real data says about its features (a building's height, a part's name), kept in the
// binary form the files carry (3D Tiles 1.1 metadata, glTF EXT_structural_metadata, 3D Tiles 1.0 batch tables made
// into the same) and read a value at a time on demand: no object per feature.
#pragma once
#include "sg/core/Material.h"
#include "sg/core/Ref.h"

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sg {

// A property's value as a program reads it: numbers after offset, scale and normalization; an enum by its name;
// VECn and MATn (column-major) and arrays as Array. Null: no value (no data and no default, or a null feature).
struct PropertyValue {
    enum class Kind : uint8_t { Null, Boolean, Integer, Unsigned, Number, String, Array };
    Kind kind = Kind::Null;
    bool boolean = false;
    int64_t integer = 0;
    uint64_t unsignedInteger = 0;
    double number = 0.0;
    std::string string;  // a STRING's, or an ENUM's name
    std::vector<PropertyValue> items;

    static PropertyValue ofBool(bool b);
    static PropertyValue ofInt(int64_t i);
    static PropertyValue ofUInt(uint64_t u);
    static PropertyValue ofNumber(double d);
    static PropertyValue ofString(std::string s);
    static PropertyValue ofArray(std::vector<PropertyValue> items);

    bool isNull() const { return kind == Kind::Null; }
    // Boolean, Integer, Unsigned and Number as a double (0 for the others).
    double asNumber() const;
    // "12.5", "true", "Main hall", "[1, 2, 3]", "null": what a viewer prints.
    std::string toString() const;
    // JSON text: numbers (integers exactly; a non-finite number as null), strings escaped, arrays.
    std::string toJson() const;
    bool operator==(const PropertyValue& o) const;
    bool operator!=(const PropertyValue& o) const { return !(*this == o); }
};

// The schema's element types (3D Tiles 1.1 metadata).
enum class PropertyType : uint8_t { Scalar, Vec2, Vec3, Vec4, Mat2, Mat3, Mat4, String, Boolean, Enum };
enum class ComponentType : uint8_t { None, Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };
// Components per element (1 for Scalar, Enum, String, Boolean; 16 for Mat4) and bytes per component (0 for None).
int componentCount(PropertyType t);
int componentBytes(ComponentType c);
// The spec's spelling ("SCALAR", "UINT16"); parse* return nullopt for any other.
const char* propertyTypeName(PropertyType t);
const char* componentTypeName(ComponentType c);
std::optional<PropertyType> parsePropertyType(const std::string& s);
std::optional<ComponentType> parseComponentType(const std::string& s);

struct EnumDef {
    std::string id, name;
    ComponentType valueType = ComponentType::UInt16;
    std::vector<std::pair<std::string, int64_t>> values;  // name, value
    const std::string* nameOf(int64_t value) const;       // null when no name has that value
};

struct ClassProperty {
    std::string id, name, description;
    PropertyType type = PropertyType::Scalar;
    ComponentType componentType = ComponentType::None;  // None for String and Boolean
    int enumIndex = -1;                                 // into Schema::enums, for Enum
    bool array = false;
    uint32_t count = 0;  // a fixed-length array's length; 0: variable length
    bool normalized = false, required = false;
    // As the schema gives them (numbers, or arrays of numbers for vectors, matrices and arrays); a property table,
    // texture or attribute may override offset, scale, min and max.
    PropertyValue offset, scale, min, max, noData, defaultValue;
};

struct ClassDef {
    std::string id, name, description;
    std::vector<ClassProperty> properties;
    int find(const std::string& propertyId) const;  // -1 when absent
};

struct Schema {
    std::string id, name, version;
    std::vector<ClassDef> classes;
    std::vector<EnumDef> enums;
    int findClass(const std::string& id) const;  // -1 when absent
    int findEnum(const std::string& id) const;
};

// What a table, texture or attribute may override of a class property's transform (Null: the class's).
struct PropertyOverrides {
    PropertyValue offset, scale, min, max;
};

// A property table's column: views into one of the store's buffers (Span: buffer -1 when absent).
struct ByteSpan {
    int buffer = -1;
    uint64_t offset = 0, size = 0;
    bool present() const { return buffer >= 0; }
};

struct PropertyColumn {
    int property = -1;  // into the class's properties
    ByteSpan values, arrayOffsets, stringOffsets;
    ComponentType arrayOffsetType = ComponentType::UInt32, stringOffsetType = ComponentType::UInt32;
    PropertyOverrides overrides;
};

struct PropertyTable {
    std::string name;
    int classIndex = -1;
    uint64_t count = 0;
    std::vector<PropertyColumn> columns;  // one per property the table has (absent ones read as their default)
    const PropertyColumn* column(int property) const;
};

// A property texture: each property read from channels of a texture at a UV set, nearest texel.
struct PropertyTextureDef {
    std::string name;
    int classIndex = -1;
    struct Property {
        int property = -1;
        ref_ptr<Texture> texture;
        int texCoord = 0;
        std::vector<uint8_t> channels;  // 0..3: R, G, B, A; bytes little-endian in that order
        PropertyOverrides overrides;
    };
    std::vector<Property> properties;
};

// A property attribute: each property a vertex attribute of the mesh (its values in MeshFeatures).
struct PropertyAttributeDef {
    std::string name;
    int classIndex = -1;
    struct Property {
        int property = -1;
        std::string attribute;  // the glTF attribute's semantic ("_TEMPERATURE")
        PropertyOverrides overrides;
    };
    std::vector<Property> properties;
};

// A raw value of property `p` as a program reads it (the transforms PropertyStore::value() applies): enum values
// (integers) named, a value equal to noData made the default (Null without one), then numbers normalized, then
// offset + scale * value, element-wise (`overrides` win over the class's offset and scale). For values that come
// as JSON (a tile's metadata) as well as for stored bytes.
PropertyValue propertyValueOf(const Schema& schema, const ClassProperty& p, PropertyValue raw,
                              const PropertyOverrides& overrides = {});

// A schema, its tables, textures and attribute definitions, and the bytes the tables read; shared (read-only once
// built) by the meshes and instances of a file or tile. Every view is checked when the table is added.
class PropertyStore : public Referenced {
public:
    PropertyStore() : serial_(nextSerial()) {}
    // Distinct for every store made in the process (a cache keyed by it never mistakes a new store for a freed one
    // at the same address).
    uint64_t serial() const { return serial_; }
    Schema schema;
    std::vector<PropertyTextureDef> propertyTextures;
    std::vector<PropertyAttributeDef> propertyAttributes;

    // A buffer's bytes, kept as they are; returns its index.
    int addBuffer(std::vector<uint8_t> bytes);
    const std::vector<uint8_t>& buffer(int i) const { return buffers_[size_t(i)]; }
    size_t bufferCount() const { return buffers_.size(); }
    // Checks every column against the schema and the buffers (class and property exist, spans inside their
    // buffers and long enough for `count` rows, offsets ascending and inside the values, enum values named):
    // std::invalid_argument naming the table's name, the property and the reason; nothing added then. Returns the
    // table's index.
    int addTable(PropertyTable table);
    const std::vector<PropertyTable>& tables() const { return tables_; }

    // Row `row` of table `t`, property `property` of its class: the raw value, noData made the default (or Null),
    // then normalized, offset and scaled. Null for a row past the table. Throws std::out_of_range for a bad t or
    // property index.
    PropertyValue value(int t, uint64_t row, int property) const;
    // Every property of the class, in the schema's order, by id.
    std::vector<std::pair<std::string, PropertyValue>> row(int t, uint64_t row) const;
    // A value of property `property` of class `classIndex` from raw little-endian bytes of one element (a
    // property texture's texel, a property attribute's vertex): the same transforms as value().
    PropertyValue decode(int classIndex, int property, const uint8_t* bytes, size_t size,
                         const PropertyOverrides& overrides) const;
    // The bytes the store holds (buffers and their bookkeeping), for a memory budget and the benchmarks.
    size_t bytes() const;

private:
    static uint64_t nextSerial() {
        static std::atomic<uint64_t> n{0};
        return ++n;
    }
    uint64_t serial_;
    std::vector<std::vector<uint8_t>> buffers_;
    std::vector<PropertyTable> tables_;
};

}  // namespace sg
