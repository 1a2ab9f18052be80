// The small JSON helpers the glTF feature extensions' reader and writer share (GltfMetadata.cpp): tinygltf's
// extension values to nlohmann::ordered_json and back, checked integers and channel lists. Internal: not installed.
#pragma once
#include "sg/core/Properties.h"

#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace sg::gltf {

// tinygltf 2.7.0 hands extensions over as its own Value; the shared metadata reader takes nlohmann::ordered_json.
nlohmann::ordered_json toJson(const tinygltf::Value& v);
// Extension `name` of an element (null when it has none), from the element's JSON text as the file has it when
// tinygltf kept it (its own values cut integers to int, which a nullFeatureId of 4294967295 is not), else from
// tinygltf's value.
nlohmann::ordered_json extensionJson(const tinygltf::ExtensionMap& x, const std::string& original, const char* name);
// And back, for the writer (integers beyond int's range as doubles, as tinygltf holds them).
tinygltf::Value toValue(const nlohmann::ordered_json& j);
// Member `key` of object `o`, or null (also when `o` is not an object).
const nlohmann::ordered_json* member(const nlohmann::ordered_json& o, const char* key);
// A whole number in [lo, hi]; LoadError(file, path) otherwise.
int64_t integer(const std::string& file, const nlohmann::ordered_json& j, const std::string& path, int64_t lo,
                int64_t hi);
// A texture's channels (each 0..3), [0] when `j` is null; LoadError(file, path) for anything else.
std::vector<uint8_t> channels(const std::string& file, const nlohmann::ordered_json* j, const std::string& path);
// The bytes of one element of a property (a fixed-length array's all): 0 for STRING, BOOLEAN and variable-length
// arrays, which neither a texture's channels nor a vertex attribute can hold.
size_t elementBytes(const Schema& schema, const ClassProperty& p);

}  // namespace sg::gltf
