// The JSON of 3D Tiles 1.1 metadata, which glTF's EXT_structural_metadata shares: a schema, a property table's
// columns, the overrides of a class property's transform, and values as the schema writes them; read into the
// property store's types (sg/core/Properties.h) and written back. Internal: not installed.
#pragma once
#include "loaders/gltf/Gltf.h"  // sg::LoadError
#include "sg/core/Properties.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>

namespace sg::metadata {

// Each throws LoadError(file, the JSON path of the element at fault, the reason) where the input is unusable and
// adds a warning (naming the path) where a part can be left out.
struct Context {
    std::string file;
    std::vector<std::string>* warnings = nullptr;
    void warn(const std::string& path, const std::string& what) const {
        if (warnings) warnings->push_back(path + ": " + what);
    }
};

// A schema object at `path` ("extensions.EXT_structural_metadata.schema", "schema"): classes, enums, every
// property's type, componentType, enumType, array, count, normalized, offset, scale, min, max, noData, default
// checked against the type.
Schema parseSchema(const nlohmann::ordered_json& j, const Context& c, const std::string& path);

// A property table object: its class (which must be in `schema`), count and columns. `view(index, path)` gives
// the store's span for a bufferView index named at `path` (and throws LoadError for a bad one).
using ViewLookup = std::function<ByteSpan(int64_t view, const std::string& path)>;
PropertyTable parsePropertyTable(const nlohmann::ordered_json& j, const Schema& schema, const ViewLookup& view,
                                 const Context& c, const std::string& path);

// The offset, scale, min and max members of a table's, texture's or attribute's property.
PropertyOverrides parseOverrides(const nlohmann::ordered_json& j, const ClassProperty& p, const Context& c,
                                 const std::string& path);

// A JSON value as a PropertyValue (numbers: integers kept exact; strings; booleans; arrays), and back.
PropertyValue valueOf(const nlohmann::ordered_json& j);
nlohmann::ordered_json jsonOf(const PropertyValue& v);

// A schema as its JSON (what saveGltf and writeTileset write); parseSchema reads it back equal.
nlohmann::ordered_json schemaJson(const Schema& schema);

}  // namespace sg::metadata
