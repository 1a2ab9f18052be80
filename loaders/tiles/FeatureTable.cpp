// What the 3D Tiles 1.0 binary formats share: the header, the table sections and the feature table's reads. Every
// length and offset read from the file is checked against the bytes before use.
#include "loaders/tiles/internal/FeatureTable.h"

#include "loaders/gltf/internal/GltfDetail.h"  // kMaxJsonDepth, fail()

#include <cmath>
#include <cstdio>
#include <limits>

namespace sg::tiles {

using gltf::fail;
using nlohmann::json;

namespace {

template <class T>
std::string str(T v) {
    return std::to_string(v);
}

// Feature table JSON: an object (empty when the section is), parsed with its nesting depth bounded.
json parseFeatureJson(const std::string& file, const unsigned char* p, size_t n) {
    while (n > 0 && (p[n - 1] == ' ' || p[n - 1] == '\0')) --n;  // padding (spaces per the spec; some pad NULs)
    if (n == 0) return json::object();
    json j;
    try {
        j = json::parse(p, p + n, [&](int depth, json::parse_event_t event, json&) {
            if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
                depth >= gltf::kMaxJsonDepth)
                fail(file, "featureTable", "JSON nested deeper than " + str(gltf::kMaxJsonDepth) + " levels");
            return true;
        });
    } catch (const json::exception& e) {
        fail(file, "featureTable", std::string("JSON: ") + e.what());
    }
    if (!j.is_object()) fail(file, "featureTable", "the feature table JSON is not an object");
    return j;
}

}  // namespace

// The magic as text when printable, else in hex (it goes into a message).
std::string magicText(const unsigned char* p) {
    std::string s = "'";
    for (int i = 0; i < 4; ++i) s += (p[i] >= 0x20 && p[i] < 0x7f) ? char(p[i]) : '?';
    return s + "' (0x" + [p] {
        char hex[9];
        std::snprintf(hex, sizeof hex, "%02x%02x%02x%02x", p[0], p[1], p[2], p[3]);
        return std::string(hex);
    }() + ")";
}

// The 12 bytes every format starts with: magic, version 1, byteLength equal to the bytes given.
void checkHeader(const std::string& file, const std::string& prefix, const unsigned char* data, size_t size,
                 const char* magic, size_t headerSize) {
    if (size < headerSize)
        fail(file, prefix + "header",
             str(size) + " bytes, shorter than the " + str(headerSize) + "-byte " + magic + " header");
    if (std::memcmp(data, magic, 4) != 0)
        fail(file, prefix + "header.magic", "is " + magicText(data) + ", not '" + magic + "'");
    if (le32(data + 4) != 1) fail(file, prefix + "header.version", "version " + str(le32(data + 4)) + " (only 1)");
    if (le32(data + 8) != size)
        fail(file, prefix + "header.byteLength",
             "byteLength " + str(le32(data + 8)) + " disagrees with the " + str(size) + " bytes of the tile");
}

const json* FeatureTable::find(const char* name) const {
    auto it = json_.find(name);
    return it == json_.end() ? nullptr : &*it;
}

const unsigned char* FeatureTable::binaryRef(const char* name, const json& ref, size_t componentSize, size_t components,
                                             uint64_t count) const {
    const auto off = ref.find("byteOffset");
    if (off == ref.end() || !off->is_number_unsigned())
        fail(file, path(name) + ".byteOffset", "is missing or not a non-negative integer");
    const uint64_t o = off->get<uint64_t>();
    if (o % componentSize != 0)
        fail(file, path(name) + ".byteOffset",
             "byteOffset " + str(o) + " is not a multiple of the component size " + str(componentSize));
    const uint64_t elem = componentSize * components;
    if (o > binary.size || count > (binary.size - o) / elem)
        fail(file, path(name),
             "byteOffset " + str(o) + " + " + str(count) + " elements of " + str(elem) +
                 " bytes is past the end of the feature table binary (" + str(binary.size) + " bytes)");
    return binary.data + o;
}

void FeatureTable::fixedType(const char* name, const json& ref, const char* type) const {
    const auto t = ref.find("componentType");
    if (t != ref.end() && !(t->is_string() && t->get<std::string>() == type))
        fail(file, path(name) + ".componentType", "must be " + std::string(type) + " (or absent)");
}

std::optional<uint32_t> FeatureTable::globalUint(const char* name) const {
    const json* v = find(name);
    if (!v) return std::nullopt;
    if (v->is_object()) {
        fixedType(name, *v, "UNSIGNED_INT");
        return le32(binaryRef(name, *v, 4, 1, 1));
    }
    if (!v->is_number_unsigned() || v->get<uint64_t>() > std::numeric_limits<uint32_t>::max())
        fail(file, path(name), "must be an integer in [0, 2^32)");
    return uint32_t(v->get<uint64_t>());
}

std::optional<dvec3> FeatureTable::globalVec3(const char* name) const {
    const json* v = find(name);
    if (!v) return std::nullopt;
    dvec3 r;
    if (v->is_object()) {
        fixedType(name, *v, "FLOAT");
        const unsigned char* p = binaryRef(name, *v, 4, 3, 1);
        r = dvec3(f32(p), f32(p + 4), f32(p + 8));
    } else {
        if (!v->is_array() || v->size() != 3) fail(file, path(name), "must be an array of 3 numbers");
        for (int k = 0; k < 3; ++k) {
            if (!(*v)[k].is_number()) fail(file, path(name), "element " + str(k) + " is not a number");
            r[k] = (*v)[k].get<double>();
        }
    }
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(r[k])) fail(file, path(name), "element " + str(k) + " is not finite");
    return r;
}

const unsigned char* FeatureTable::perInstance(const char* name, const char* type, size_t componentSize,
                                               size_t components, uint32_t count) const {
    const json* v = find(name);
    if (!v) return nullptr;
    if (!v->is_object()) fail(file, path(name), "must refer to the binary body ({\"byteOffset\": ...})");
    fixedType(name, *v, type);
    return binaryRef(name, *v, componentSize, components, count);
}

Sections readSections(const std::string& file, const unsigned char* data, size_t size, size_t headerSize) {
    static const char* names[4] = {"featureTableJSONByteLength", "featureTableBinaryByteLength",
                                   "batchTableJSONByteLength", "batchTableBinaryByteLength"};
    size_t offset = headerSize, start[4];
    uint32_t len[4];
    for (int i = 0; i < 4; ++i) {
        len[i] = le32(data + 12 + 4 * i);
        if (len[i] > size - offset)  // offset <= size holds: headerSize <= size, each section checked
            fail(file, std::string("header.") + names[i],
                 str(len[i]) + " bytes at byte " + str(offset) + " exceed the " + str(size) + " bytes of the tile");
        start[i] = offset;
        offset += len[i];
    }
    Sections s{FeatureTable{file, parseFeatureJson(file, data + start[0], len[0]), Bytes{data + start[1], len[1]}},
               Bytes{data + offset, size - offset}, Bytes{data + start[2], len[2]}, Bytes{data + start[3], len[3]}};
    return s;
}

dvec3 octDecode(uint32_t ex, uint32_t ey, double range) {
    auto snorm = [range](uint32_t v) { return std::min(v / range, 1.0) * 2.0 - 1.0; };
    auto signNotZero = [](double v) { return v < 0.0 ? -1.0 : 1.0; };
    dvec3 n(snorm(ex), snorm(ey), 0.0);
    n.z = 1.0 - (std::abs(n.x) + std::abs(n.y));
    if (n.z < 0.0) {
        const double x = n.x;
        n.x = (1.0 - std::abs(n.y)) * signNotZero(x);
        n.y = (1.0 - std::abs(x)) * signNotZero(n.y);
    }
    return glm::normalize(n);  // |x| + |y| + |z| >= 1: never zero
}

std::vector<uint32_t> readBatchIds(const FeatureTable& ft, uint32_t n) {
    const json* b = ft.find("BATCH_ID");
    if (!b) return {};
    if (!b->is_object()) fail(ft.file, FeatureTable::path("BATCH_ID"), "must refer to the binary body");
    const auto t = b->find("componentType");
    const std::string type = t == b->end() ? "UNSIGNED_SHORT" : t->is_string() ? t->get<std::string>() : "";
    const size_t bytes = type == "UNSIGNED_BYTE" ? 1 : type == "UNSIGNED_SHORT" ? 2 : type == "UNSIGNED_INT" ? 4 : 0;
    if (bytes == 0)
        fail(ft.file, FeatureTable::path("BATCH_ID.componentType"),
             "must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    const unsigned char* p = ft.binaryRef("BATCH_ID", *b, bytes, 1, n);
    std::vector<uint32_t> ids(n);
    for (uint32_t i = 0; i < n; ++i) {
        const unsigned char* q = p + size_t(i) * bytes;
        ids[i] = bytes == 1 ? q[0] : bytes == 2 ? le16(q) : le32(q);
    }
    return ids;
}

}  // namespace sg::tiles
