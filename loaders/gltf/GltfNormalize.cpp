// JSON that glTF allows and tinygltf 2.7.0 refuses (or misreads), rewritten before tinygltf parses it, and the
// rewriting undone on the parsed model: integers written as floats, buffers without data, accessors of a type
// tinygltf does not know, index accessors without a buffer view.
#include "loaders/gltf/internal/GltfDetail.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

namespace sg::gltf {

namespace {

using json = nlohmann::json;

uint32_t le32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
void put32(std::string& s, uint32_t v) {
    for (int k = 0; k < 4; ++k) s.push_back(char((v >> (8 * k)) & 0xff));
}

// The smallest data URI tinygltf accepts (it refuses an empty one); the byte is dropped after parsing.
constexpr const char* kOneByte = "data:application/octet-stream;base64,AA==";

// Members (and arrays) whose numbers glTF declares integers: tinygltf skips an optional one written as a float
// ("mesh": 0.0 would lose the mesh) and refuses a required one.
bool integerKey(const std::string& k) {
    static const std::set<std::string> keys{"buffer",     "bufferView", "byteOffset",
                                            "byteLength", "byteStride", "componentType",
                                            "count",      "target",     "index",
                                            "texCoord",   "mode",       "indices",
                                            "material",   "mesh",       "camera",
                                            "skin",       "node",       "input",
                                            "output",     "sampler",    "source",
                                            "scene",      "magFilter",  "minFilter",
                                            "wrapS",      "wrapT",      "inverseBindMatrices",
                                            "skeleton",   "children",   "nodes",
                                            "joints",     "light"};
    return keys.count(k) != 0;
}

// Walks the SAX events of the JSON text: true as soon as a float stands where an integer belongs (what
// tinygltf misreads), without building the document (a .gltf may hold megabytes of data URIs).
struct FloatIntegers : json::json_sax_t {
    struct Level {
        bool array;
        std::string key;  // the member being read (objects), or the array's own key
    };
    std::vector<Level> levels;
    std::string pendingKey;
    bool found = false;

    bool integerHere() const {
        if (levels.empty()) return false;
        for (const Level& l : levels)
            if (l.key == "extras" || l.key == "extensions") return false;  // as integers() leaves them
        const Level& top = levels.back();
        if (integerKey(top.key)) return true;
        // attributes {"POSITION": 0} and morph targets [{"POSITION": 1}] name accessors by any key
        const std::string& parent = levels.size() >= 2 ? levels[levels.size() - 2].key : std::string();
        return !top.array && (parent == "attributes" || parent == "targets");
    }
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override {
        found = found || integerHere();
        return !found;  // one is enough: stop reading
    }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override {
        levels.push_back({false, levels.empty() || !levels.back().array ? pendingKey : levels.back().key});
        return true;
    }
    bool key(string_t& k) override {
        levels.back().key = k;
        pendingKey = k;
        return true;
    }
    bool end_object() override {
        levels.pop_back();
        return true;
    }
    bool start_array(std::size_t) override {
        levels.push_back({true, levels.empty() || !levels.back().array ? pendingKey : levels.back().key});
        return true;
    }
    bool end_array() override {
        levels.pop_back();
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const json::exception&) override { return false; }
};

// Floats standing for integers made integers; a number with a fraction where glTF wants an integer is refused,
// naming its path. `accessorMap`: an object whose members all name accessors (attributes, morph targets).
// Extensions are left as they are: tinygltf keeps their numbers as written, and their readers judge them.
void integers(const std::string& file, json& v, const std::string& path, bool isInteger, bool accessorMap,
              size_t& changed) {
    if (v.is_number_float()) {
        if (!isInteger) return;
        const double d = v.get<double>();
        if (!(std::isfinite(d) && d == std::floor(d) && std::abs(d) <= 9007199254740992.0))
            fail(file, path, "must be an integer, not " + v.dump());
        v = json(int64_t(d));
        ++changed;
    } else if (v.is_array()) {
        for (size_t i = 0; i < v.size(); ++i) integers(file, v[i], at(path, i), isInteger, accessorMap, changed);
    } else if (v.is_object()) {
        for (auto it = v.begin(); it != v.end(); ++it) {
            const std::string& k = it.key();
            if (k == "extras" || k == "extensions") continue;
            integers(file, it.value(), path.empty() ? k : path + "." + k, accessorMap || integerKey(k),
                     k == "attributes" || k == "targets", changed);
        }
    }
}

// Buffers without data in the file (no uri, other than a GLB's buffer 0 over its BIN chunk): a one-byte data URI.
void absentBuffers(json& doc, bool hasBin, Normalized& out) {
    if (!doc.contains("buffers") || !doc["buffers"].is_array()) return;
    json& buffers = doc["buffers"];
    for (size_t i = 0; i < buffers.size(); ++i) {
        json& b = buffers[i];
        if (!b.is_object() || b.contains("uri") || (hasBin && i == 0)) continue;
        out.absentBuffers.push_back(i);
        b["uri"] = kOneByte;
        b["byteLength"] = 1;
    }
}

// Accessors of a type tinygltf refuses, and index accessors without a view (zeros, which tinygltf refuses).
void accessors(json& doc, Normalized& out) {
    if (!doc.contains("accessors") || !doc["accessors"].is_array()) return;
    json& acc = doc["accessors"];
    static const std::set<std::string> types{"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
    for (size_t i = 0; i < acc.size(); ++i) {
        json& a = acc[i];
        if (!a.is_object() || !a.contains("type") || !a["type"].is_string()) continue;
        const std::string type = a["type"].get<std::string>();
        if (types.count(type)) continue;
        out.unknownTypes.push_back(i);
        out.warnings.push_back(at("accessors", i) + ".type: unknown type '" + type + "', the accessor is not read");
        a["type"] = "SCALAR";
    }
    const bool views = doc.contains("bufferViews") && doc["bufferViews"].is_array() && !doc["bufferViews"].empty();
    if (!views || !doc.contains("meshes") || !doc["meshes"].is_array()) return;
    for (const json& mesh : doc["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (const json& p : mesh["primitives"]) {
            if (!p.is_object() || !p.contains("indices") || !p["indices"].is_number_unsigned()) continue;
            const size_t i = p["indices"].get<size_t>();
            if (i >= acc.size() || !acc[i].is_object() || acc[i].contains("bufferView")) continue;
            out.viewlessIndices.push_back(i);
            acc[i]["bufferView"] = 0;  // any view: undone after parsing
        }
    }
}

}  // namespace

bool needsNormalizing(const unsigned char* data, size_t size) {
    FloatIntegers sax;
    json::sax_parse(data, data + size, &sax, json::input_format_t::json, false);
    return sax.found;
}

bool normalizeForTinygltf(const std::string& file, const unsigned char* data, size_t size, bool binary,
                          Normalized& out) {
    // prevalidate() has checked the GLB's header and chunk lengths.
    const unsigned char* text = binary ? data + 20 : data;
    const size_t textSize = binary ? le32(data + 12) : size;
    const size_t length = binary ? le32(data + 8) : size;
    const bool hasBin = binary && 20 + textSize + 8 <= length;
    json doc = json::parse(text, text + textSize, nullptr, false);
    if (!doc.is_object()) return false;  // tinygltf says what is wrong with it
    size_t changed = 0;
    integers(file, doc, "", false, false, changed);
    absentBuffers(doc, hasBin, out);
    accessors(doc, out);
    if (changed == 0 && out.absentBuffers.empty() && out.unknownTypes.empty() && out.viewlessIndices.empty())
        return false;
    std::string text2;
    try {
        text2 = doc.dump();
    } catch (const json::exception&) {  // text that is not UTF-8: tinygltf says what it makes of it
        out = Normalized();
        return false;
    }
    if (!binary) {
        out.bytes = std::move(text2);
        return true;
    }
    text2.append((4 - text2.size() % 4) % 4, ' ');
    const size_t rest = length - 20 - textSize;  // the BIN chunk and any other, as they are
    out.bytes.clear();
    out.bytes.append("glTF");
    put32(out.bytes, 2);
    put32(out.bytes, uint32_t(20 + text2.size() + rest));
    put32(out.bytes, uint32_t(text2.size()));
    put32(out.bytes, 0x4E4F534Au);  // "JSON"
    out.bytes += text2;
    out.bytes.append(reinterpret_cast<const char*>(data) + 20 + textSize, rest);
    return true;
}

void undoNormalizing(const Normalized& n, tinygltf::Model& m) {
    for (size_t i : n.absentBuffers) {
        m.buffers[i].data.clear();
        m.buffers[i].uri.clear();
    }
    for (size_t i : n.unknownTypes) {  // validate() skips it; any use of it is refused by its type
        tinygltf::Accessor& a = m.accessors[i];
        a.type = kUnknownType;
        a.bufferView = -1;
        a.sparse.isSparse = false;
    }
    for (size_t i : n.viewlessIndices) m.accessors[i].bufferView = -1;
}

}  // namespace sg::gltf
