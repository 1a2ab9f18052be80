// Small readers the metadata JSON files share (loaders/metadata/MetadataJson.cpp, MetadataSchema.cpp): members of
// a JSON object checked for their type, and a value checked against a class property's shape. Internal: not
// installed.
#pragma once
#include "loaders/metadata/internal/MetadataJson.h"

#include <string>

namespace sg::metadata::fields {

[[noreturn]] void fail(const Context& c, const std::string& path, const std::string& reason);
// Member `key` of object `o`, or null when absent.
const nlohmann::ordered_json* member(const nlohmann::ordered_json& o, const char* key);
// A string member (empty when absent; LoadError when required and absent, or not a string). `path` is the object's.
std::string text(const nlohmann::ordered_json& o, const char* key, const Context& c, const std::string& path,
                 bool required = false);
// A boolean member (false when absent).
bool flag(const nlohmann::ordered_json& o, const char* key, const Context& c, const std::string& path);

// What the innermost values of a property's noData, default, offset, ... are: numbers (SCALAR, VECn, MATn), strings
// (STRING, and an ENUM's names) or booleans.
enum class Leaf { Number, String, Boolean };
Leaf leafOf(const ClassProperty& p);
// Checks that `v` has the shape the spec gives values of `p`: a leaf for a scalar, an array of N for VECn and
// N * N for MATn; for an array property an array (of `count` when fixed) of those. LoadError at `path` otherwise.
void checkShape(const nlohmann::ordered_json& v, const ClassProperty& p, Leaf leaf, const Context& c,
                const std::string& path);

}  // namespace sg::metadata::fields
