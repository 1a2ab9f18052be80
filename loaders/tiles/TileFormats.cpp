// The 3D Tiles 1.0 binary formats b3dm, i3dm and cmpt: their semantics and the payload after the batch table (the
// header and feature table reads they share are FeatureTable.cpp's). Every length and offset read from the file is
// checked against the bytes before use; the batch table is bounded here and read by BatchTable.cpp.
#include "loaders/tiles/internal/TileFormats.h"

#include "loaders/gltf/internal/GltfDetail.h"  // at(), fail()
#include "loaders/tiles/internal/FeatureTable.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <tuple>
#include <utility>

namespace sg::tiles {
namespace {

using glm::dmat3;
using gltf::at;
using gltf::fail;
using nlohmann::json;

// A composite inside a composite inside ... may go this deep (recursion and memory stay bounded).
constexpr int kMaxCmptDepth = 8;
// Legacy b3dm headers put a JSON string ('"', 0x22) or the glTF magic ('g', 0x67) where the current header has
// a batch table length; a first byte of 0x22 or more makes the length at least this (as CesiumJS tests it).
constexpr uint32_t kLegacyLength = 0x22000000;
// WGS84 (the ellipsoid EAST_NORTH_UP refers to).
constexpr double kWgs84A = 6378137.0, kWgs84B = 6356752.3142451793;

template <class T>
std::string str(T v) {
    return std::to_string(v);
}

// The glb after the tables, by its own header's length (the tile may pad after it).
Bytes embeddedGlb(const std::string& file, Bytes body) {
    if (body.size < 12) fail(file, "glb", "the embedded glb is " + str(body.size) + " bytes, under its 12-byte header");
    if (std::memcmp(body.data, "glTF", 4) != 0)
        fail(file, "glb", "the embedded glTF starts with " + magicText(body.data) + ", not 'glTF'");
    const uint32_t length = le32(body.data + 8);
    if (length < 12 || length > body.size)
        fail(file, "glb", "the embedded glb's length " + str(length) + " is outside [12, " + str(body.size) + "]");
    return Bytes{body.data, length};
}

// A unit vector along v (not zero, finite), scaled first so that squaring its parts cannot overflow or underflow.
dvec3 direction(dvec3 v) {
    v /= std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    return glm::normalize(v);
}

// East, north, up of WGS84 at an ECEF position (CesiumJS' eastNorthUpToFixedFrame): up is the ellipsoid
// normal, east is horizontal. On the polar axis, where east is undefined, its fixed frame for the pole's side.
dmat3 eastNorthUp(const dvec3& p) {
    if (std::abs(p.x) < 1e-14 && std::abs(p.y) < 1e-14) {
        const double s = p.z < 0.0 ? -1.0 : 1.0;
        return dmat3(dvec3(0, 1, 0), dvec3(-s, 0, 0), dvec3(0, 0, s));
    }
    // The gradient of x²/a² + y²/a² + z²/b² (a² factored out), of p scaled to 1 first: p may be as large as
    // doubles go.
    const dvec3 q = p / std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    const dvec3 up = direction(dvec3(q.x, q.y, q.z * (kWgs84A / kWgs84B) * (kWgs84A / kWgs84B)));
    const dvec3 east = direction(dvec3(-p.y, p.x, 0.0));
    return dmat3(east, glm::cross(up, east), up);
}

// Checks a right/up pair and makes the rotation whose columns are right, up, right x up.
dmat3 basis(const std::string& file, const char* name, uint32_t i, dvec3 right, dvec3 up) {
    for (const dvec3* v : {&right, &up}) {
        const double len = glm::length(*v);
        if (!std::isfinite(len) || len < 1e-6)
            fail(file, FeatureTable::path(name),
                 "instance " + str(i) + ": zero-length or non-finite " + (v == &up ? "up" : "right") + " normal");
    }
    right = glm::normalize(right);
    up = glm::normalize(up);
    const dvec3 forward = glm::cross(right, up);
    if (glm::length(forward) < 1e-6)
        fail(file, FeatureTable::path(name), "instance " + str(i) + ": the up and right normals are parallel");
    return dmat3(right, up, glm::normalize(forward));
}

void collectTiles(const std::string& file, const std::string& prefix, const unsigned char* data, size_t size, int depth,
                  std::vector<Bytes>& out) {
    if (depth > kMaxCmptDepth)
        fail(file, prefix.empty() ? "" : prefix.substr(0, prefix.size() - 1),
             "composite tiles nested deeper than " + str(kMaxCmptDepth) + " levels");
    checkHeader(file, prefix, data, size, "cmpt", 16);
    const uint32_t tilesLength = le32(data + 12);
    size_t offset = 16;
    // Each inner tile takes at least 12 bytes, so the loop ends with the data whatever tilesLength says.
    for (uint32_t i = 0; i < tilesLength; ++i) {
        const std::string path = prefix + at("tiles", i);
        if (size - offset < 12)
            fail(file, path,
                 "tile " + str(i) + " of " + str(tilesLength) + " starts at byte " + str(offset) + ", " +
                     str(size - offset) + " bytes before the end: no room for its 12-byte header");
        const unsigned char* tile = data + offset;
        const uint32_t length = le32(tile + 8);
        if (length < 12 || length > size - offset)
            fail(file, path + ".header.byteLength",
                 "byteLength " + str(length) + " is outside [12, " + str(size - offset) + "] (the bytes left)");
        if (std::memcmp(tile, "cmpt", 4) == 0)
            collectTiles(file, path + ".", tile, length, depth + 1, out);
        else if (std::memcmp(tile, "b3dm", 4) == 0 || std::memcmp(tile, "i3dm", 4) == 0 ||
                 std::memcmp(tile, "pnts", 4) == 0)
            out.push_back(Bytes{tile, length});
        else
            fail(file, path + ".header.magic", "unknown tile format " + magicText(tile));
        offset += length;
    }
}

// An i3dm's glTF after the tables: the embedded glb (gltfFormat 1) or its URI (0).
void readGltf(const std::string& file, uint32_t gltfFormat, Bytes body, I3dm& r) {
    if (gltfFormat == 1) {
        r.glb = embeddedGlb(file, body);
    } else {
        size_t n = body.size;
        while (n > 0 && (body.data[n - 1] == ' ' || body.data[n - 1] == '\0')) --n;
        if (n == 0) fail(file, "glbUri", "gltfFormat 0 with an empty glTF URI");
        r.glbUri.assign(reinterpret_cast<const char*>(body.data), n);
    }
}

// An i3dm's per-instance arrays in the feature table's binary body (null when absent) and the globals they need.
struct InstanceColumns {
    const unsigned char* pos = nullptr;
    const unsigned char* quantized = nullptr;
    dvec3 qOffset{0.0}, qScale{0.0};
    const unsigned char *up = nullptr, *right = nullptr;
    const unsigned char *upOct = nullptr, *rightOct = nullptr;
    bool enu = false;
    const unsigned char *scale = nullptr, *scale3 = nullptr;
};

void readPositions(const FeatureTable& ft, uint32_t n, InstanceColumns& c) {
    c.pos = ft.perInstance("POSITION", "FLOAT", 4, 3, n);
    c.quantized = c.pos ? nullptr : ft.perInstance("POSITION_QUANTIZED", "UNSIGNED_SHORT", 2, 3, n);
    if (!c.pos && !c.quantized)
        fail(ft.file, FeatureTable::path("POSITION"), "neither POSITION nor POSITION_QUANTIZED");
    if (c.quantized) {
        for (const char* name : {"QUANTIZED_VOLUME_OFFSET", "QUANTIZED_VOLUME_SCALE"})
            if (!ft.find(name)) fail(ft.file, FeatureTable::path(name), "is missing (POSITION_QUANTIZED needs it)");
        c.qOffset = *ft.globalVec3("QUANTIZED_VOLUME_OFFSET");
        c.qScale = *ft.globalVec3("QUANTIZED_VOLUME_SCALE");
    }
}

// An up/right pair of per-instance normals: both or neither.
std::pair<const unsigned char*, const unsigned char*> normalPair(const FeatureTable& ft, uint32_t n, const char* upName,
                                                                 const char* rightName, const char* type, size_t size,
                                                                 size_t comps) {
    const unsigned char* up = ft.perInstance(upName, type, size, comps, n);
    const unsigned char* right = ft.perInstance(rightName, type, size, comps, n);
    if (!up != !right)
        fail(ft.file, FeatureTable::path(up ? rightName : upName), "is missing (the other normal is given)");
    return std::make_pair(up, right);
}

// Orientation: float normals win over oct-encoded ones (the spec's "higher precision"); each needs its pair.
void readOrientations(const FeatureTable& ft, uint32_t n, InstanceColumns& c) {
    std::tie(c.up, c.right) = normalPair(ft, n, "NORMAL_UP", "NORMAL_RIGHT", "FLOAT", 4, 3);
    if (!c.up)
        std::tie(c.upOct, c.rightOct) =
            normalPair(ft, n, "NORMAL_UP_OCT32P", "NORMAL_RIGHT_OCT32P", "UNSIGNED_SHORT", 2, 2);
    if (const json* e = ft.find("EAST_NORTH_UP")) {
        if (!e->is_boolean()) fail(ft.file, FeatureTable::path("EAST_NORTH_UP"), "must be true or false");
        c.enu = e->get<bool>();
    }
}

// v, checked finite: the error names the property and the instance.
dvec3 requireFinite(const std::string& file, const char* name, uint32_t i, dvec3 v) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        fail(file, FeatureTable::path(name), "instance " + str(i) + ": not finite");
    return v;
}

// Instance i's position in the tile's frame: RTC_CENTER + POSITION or the dequantized POSITION_QUANTIZED.
dvec3 instancePosition(const std::string& file, const InstanceColumns& c, const dvec3& rtc, uint32_t i) {
    dvec3 p;
    if (c.pos) {
        const unsigned char* q = c.pos + 12 * size_t(i);
        p = dvec3(f32(q), f32(q + 4), f32(q + 8));
    } else {
        const unsigned char* q = c.quantized + 6 * size_t(i);
        p = dvec3(le16(q), le16(q + 2), le16(q + 4)) * c.qScale / 65535.0 + c.qOffset;
    }
    return requireFinite(file, c.pos ? "POSITION" : "POSITION_QUANTIZED", i, p + rtc);
}

// Instance i's rotation, at position p: from its normals, east-north-up, or none.
dmat3 instanceRotation(const std::string& file, const InstanceColumns& c, uint32_t i, const dvec3& p) {
    if (c.up) {
        const unsigned char* u = c.up + 12 * size_t(i);
        const unsigned char* rt = c.right + 12 * size_t(i);
        return basis(file, "NORMAL_UP", i, dvec3(f32(rt), f32(rt + 4), f32(rt + 8)),
                     dvec3(f32(u), f32(u + 4), f32(u + 8)));
    }
    if (c.upOct) {
        const unsigned char* u = c.upOct + 4 * size_t(i);
        const unsigned char* rt = c.rightOct + 4 * size_t(i);
        return basis(file, "NORMAL_UP_OCT32P", i, octDecode(le16(rt), le16(rt + 2), 65535.0),
                     octDecode(le16(u), le16(u + 2), 65535.0));
    }
    if (c.enu) return eastNorthUp(p);
    return dmat3(1.0);
}

// Instance i's scale: SCALE times SCALE_NON_UNIFORM, 1 where neither is given.
dvec3 instanceScale(const std::string& file, const InstanceColumns& c, uint32_t i) {
    dvec3 s(1.0);
    if (c.scale) s *= requireFinite(file, "SCALE", i, dvec3(f32(c.scale + 4 * size_t(i))));
    if (c.scale3) {
        const unsigned char* q = c.scale3 + 12 * size_t(i);
        s *= requireFinite(file, "SCALE_NON_UNIFORM", i, dvec3(f32(q), f32(q + 4), f32(q + 8)));
    }
    return s;
}

// translate(RTC_CENTER + position) * rotation * scale, with each part checked in that order.
dmat4 instanceMatrix(const std::string& file, const InstanceColumns& c, const dvec3& rtc, uint32_t i) {
    const dvec3 p = instancePosition(file, c, rtc, i);
    const dmat3 rot = instanceRotation(file, c, i, p);
    const dvec3 s = instanceScale(file, c, i);
    return glm::translate(dmat4(1.0), p) * dmat4(rot) * glm::scale(dmat4(1.0), s);
}

}  // namespace

ContentKind sniffContent(const unsigned char* data, size_t size) {
    if (size >= 4) {
        static const std::pair<const char*, ContentKind> magics[] = {{"glTF", ContentKind::Glb},
                                                                     {"b3dm", ContentKind::B3dm},
                                                                     {"i3dm", ContentKind::I3dm},
                                                                     {"cmpt", ContentKind::Cmpt},
                                                                     {"pnts", ContentKind::Pnts}};
        for (const auto& [magic, kind] : magics)
            if (std::memcmp(data, magic, 4) == 0) return kind;
    }
    size_t i = size >= 3 && data[0] == 0xef && data[1] == 0xbb && data[2] == 0xbf ? 3 : 0;
    while (i < size && (data[i] == ' ' || data[i] == '\t' || data[i] == '\n' || data[i] == '\r')) ++i;
    return i < size && data[i] == '{' ? ContentKind::Json : ContentKind::Unknown;
}

B3dm parseB3dm(const std::string& file, const unsigned char* data, size_t size) {
    checkHeader(file, "", data, size, "b3dm", 28);
    // The legacy layouts (before 3D Tiles 1.0) are not read: refused by name so the user knows what the file is.
    if (le32(data + 20) >= kLegacyLength)
        fail(file, "header",
             "legacy b3dm header [batchLength] [batchTableByteLength] (20 bytes, before 3D Tiles 1.0) is not "
             "supported");
    if (le32(data + 24) >= kLegacyLength)
        fail(file, "header",
             "legacy b3dm header [batchTableJsonByteLength] [batchTableBinaryByteLength] [batchLength] (24 bytes, "
             "before 3D Tiles 1.0) is not supported");
    const Sections s = readSections(file, data, size, 28);
    B3dm b;
    // BATCH_LENGTH is required by the spec, yet CesiumJS reads tiles without it as 0 features: so does this.
    b.batchLength = s.featureTable.globalUint("BATCH_LENGTH").value_or(0);
    if (const auto rtc = s.featureTable.globalVec3("RTC_CENTER")) {
        b.hasRtcCenter = true;
        b.rtcCenter = *rtc;
    }
    b.glb = embeddedGlb(file, s.body);
    b.batchJson = s.batchJson;
    b.batchBinary = s.batchBinary;
    return b;
}

I3dm parseI3dm(const std::string& file, const unsigned char* data, size_t size) {
    checkHeader(file, "", data, size, "i3dm", 32);
    const uint32_t gltfFormat = le32(data + 28);
    if (gltfFormat > 1) fail(file, "header.gltfFormat", "gltfFormat " + str(gltfFormat) + " (0: URI, 1: glb)");
    const Sections s = readSections(file, data, size, 32);
    const FeatureTable& ft = s.featureTable;
    I3dm r;
    readGltf(file, gltfFormat, s.body, r);

    const std::optional<uint32_t> count = ft.globalUint("INSTANCES_LENGTH");
    if (!count) fail(file, FeatureTable::path("INSTANCES_LENGTH"), "is missing (required)");
    const uint32_t n = *count;
    const dvec3 rtc = ft.globalVec3("RTC_CENTER").value_or(dvec3(0.0));

    // Each array is checked to hold INSTANCES_LENGTH elements before anything is allocated for them.
    InstanceColumns columns;
    readPositions(ft, n, columns);
    readOrientations(ft, n, columns);
    columns.scale = ft.perInstance("SCALE", "FLOAT", 4, 1, n);
    columns.scale3 = ft.perInstance("SCALE_NON_UNIFORM", "FLOAT", 4, 3, n);
    r.batchIds = readBatchIds(ft, n);
    r.batchJson = s.batchJson;
    r.batchBinary = s.batchBinary;

    r.instances.reserve(n);
    for (uint32_t i = 0; i < n; ++i) r.instances.push_back(instanceMatrix(file, columns, rtc, i));
    return r;
}

Cmpt parseCmpt(const std::string& file, const unsigned char* data, size_t size) {
    Cmpt c;
    collectTiles(file, "", data, size, 1, c.tiles);
    return c;
}

uint32_t pntsPointCount(const std::string& file, const unsigned char* data, size_t size) {
    checkHeader(file, "", data, size, "pnts", 28);
    const Sections s = readSections(file, data, size, 28);
    const std::optional<uint32_t> n = s.featureTable.globalUint("POINTS_LENGTH");
    if (!n) fail(file, FeatureTable::path("POINTS_LENGTH"), "is missing (required)");
    return *n;
}

}  // namespace sg::tiles
