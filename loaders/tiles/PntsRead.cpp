// A point cloud tile's feature table semantics into a points Mesh. Positions are kept as floats relative to a
// double origin (RTC_CENTER, plus the quantized volume's offset) so that points far from the tileset's origin stay
// exact. Where the spec ranks semantics, the higher precision wins: POSITION over POSITION_QUANTIZED, NORMAL over
// NORMAL_OCT16P, and RGBA over RGB over RGB565 over CONSTANT_RGBA.
#include "loaders/gltf/internal/GltfDetail.h"  // fail
#include "loaders/tiles/internal/BatchTable.h"
#include "loaders/tiles/internal/Pnts.h"
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/core/Features.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace sg::tiles {
namespace {

using gltf::fail;
using nlohmann::json;

std::string str(uint64_t v) { return std::to_string(v); }

// What the semantics give, before they become a Mesh.
struct Points {
    dvec3 origin{0.0};
    std::vector<vec3> positions, normals;
    std::vector<vec4> colors;
    std::optional<vec4> constant;  // CONSTANT_RGBA
    std::vector<uint32_t> batchIds;
    bool hasBatchIds = false;
};

void requireFinite(const std::string& file, const char* name, const std::vector<vec3>& v) {
    for (size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i].x) || !std::isfinite(v[i].y) || !std::isfinite(v[i].z))
            fail(file, FeatureTable::path(name), "point " + str(i) + ": not finite");
}

std::vector<vec3> vec3s(const std::vector<float>& f) {
    std::vector<vec3> v(f.size() / 3);
    for (size_t i = 0; i < v.size(); ++i) v[i] = vec3(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
    return v;
}

// POSITION (float32, relative to RTC_CENTER) or POSITION_QUANTIZED (uint16 across the quantized volume, relative
// to its offset: the offset goes into the origin, the scale into the floats).
void readPositions(const FeatureTable& ft, uint32_t n, const PntsDraco* draco, Points& p) {
    const dvec3 rtc = ft.globalVec3("RTC_CENTER").value_or(dvec3(0.0));
    p.origin = rtc;
    if (draco && draco->has("POSITION")) {
        p.positions = vec3s(draco->values<float>("POSITION", 3));
    } else if (const unsigned char* q = ft.perInstance("POSITION", "FLOAT", 4, 3, n)) {
        p.positions.resize(n);
        for (uint32_t i = 0; i < n; ++i, q += 12) p.positions[i] = vec3(f32(q), f32(q + 4), f32(q + 8));
    } else if (const unsigned char* qq = ft.perInstance("POSITION_QUANTIZED", "UNSIGNED_SHORT", 2, 3, n)) {
        for (const char* name : {"QUANTIZED_VOLUME_OFFSET", "QUANTIZED_VOLUME_SCALE"})
            if (!ft.find(name)) fail(ft.file, FeatureTable::path(name), "is missing (POSITION_QUANTIZED needs it)");
        const dvec3 offset = *ft.globalVec3("QUANTIZED_VOLUME_OFFSET");
        const dvec3 scale = *ft.globalVec3("QUANTIZED_VOLUME_SCALE") / 65535.0;
        p.origin = rtc + offset;
        p.positions.resize(n);
        for (uint32_t i = 0; i < n; ++i, qq += 6)
            p.positions[i] = vec3(dvec3(le16(qq), le16(qq + 2), le16(qq + 4)) * scale);
        requireFinite(ft.file, "QUANTIZED_VOLUME_SCALE", p.positions);  // a huge scale overflows the floats
        return;
    } else {
        fail(ft.file, FeatureTable::path("POSITION"), "neither POSITION nor POSITION_QUANTIZED");
    }
    requireFinite(ft.file, "POSITION", p.positions);
}

vec4 rgba(const unsigned char* q, int comps) {
    return vec4(q[0] / 255.0f, q[1] / 255.0f, q[2] / 255.0f, comps == 4 ? q[3] / 255.0f : 1.0f);
}

// CONSTANT_RGBA: 4 integers in [0, 255] in the JSON, or 4 UNSIGNED_BYTEs in the binary body.
std::optional<vec4> constantColor(const FeatureTable& ft) {
    const json* v = ft.find("CONSTANT_RGBA");
    if (!v) return std::nullopt;
    unsigned char c[4];
    if (v->is_object()) {
        ft.fixedType("CONSTANT_RGBA", *v, "UNSIGNED_BYTE");
        std::copy_n(ft.binaryRef("CONSTANT_RGBA", *v, 1, 4, 1), 4, c);
    } else {
        if (!v->is_array() || v->size() != 4)
            fail(ft.file, FeatureTable::path("CONSTANT_RGBA"), "must be an array of 4 integers in [0, 255]");
        for (int k = 0; k < 4; ++k) {
            const json& e = (*v)[size_t(k)];
            if (!e.is_number_unsigned() || e.get<uint64_t>() > 255)
                fail(ft.file, FeatureTable::path("CONSTANT_RGBA"),
                     "element " + str(uint64_t(k)) + " is not in [0, 255]");
            c[k] = uint8_t(e.get<uint64_t>());
        }
    }
    return rgba(c, 4);
}

// Per-point colours from RGBA, RGB or RGB565 (5, 6 and 5 bits), else the constant colour.
void readColors(const FeatureTable& ft, uint32_t n, const PntsDraco* draco, Points& p) {
    for (int comps : {4, 3}) {
        const char* name = comps == 4 ? "RGBA" : "RGB";
        const unsigned char* q = nullptr;
        std::vector<uint8_t> decoded;
        if (draco && draco->has(name)) {
            decoded = draco->values<uint8_t>(name, comps);
            q = decoded.data();
        } else {
            q = ft.perInstance(name, "UNSIGNED_BYTE", 1, size_t(comps), n);
        }
        if (!q) continue;
        p.colors.resize(n);
        for (uint32_t i = 0; i < n; ++i) p.colors[i] = rgba(q + size_t(i) * size_t(comps), comps);
        return;
    }
    if (const unsigned char* q = ft.perInstance("RGB565", "UNSIGNED_SHORT", 2, 1, n)) {
        p.colors.resize(n);
        for (uint32_t i = 0; i < n; ++i) {
            const uint16_t c = le16(q + 2 * size_t(i));
            p.colors[i] = vec4(float(c >> 11) / 31.0f, float((c >> 5) & 63) / 63.0f, float(c & 31) / 31.0f, 1.0f);
        }
        return;
    }
    p.constant = constantColor(ft);
}

void readNormals(const FeatureTable& ft, uint32_t n, const PntsDraco* draco, Points& p) {
    if (draco && draco->has("NORMAL")) {
        p.normals = vec3s(draco->values<float>("NORMAL", 3));
    } else if (const unsigned char* q = ft.perInstance("NORMAL", "FLOAT", 4, 3, n)) {
        p.normals.resize(n);
        for (uint32_t i = 0; i < n; ++i, q += 12) p.normals[i] = vec3(f32(q), f32(q + 4), f32(q + 8));
    } else if (const unsigned char* o = ft.perInstance("NORMAL_OCT16P", "UNSIGNED_BYTE", 1, 2, n)) {
        p.normals.resize(n);
        for (uint32_t i = 0; i < n; ++i, o += 2) p.normals[i] = vec3(octDecode(o[0], o[1], 255.0));
    }
}

void readBatch(const FeatureTable& ft, uint32_t n, const PntsDraco* draco, Points& p) {
    if (draco && draco->has("BATCH_ID")) {
        const json& b = *ft.find("BATCH_ID");  // has() checked the semantic is there
        const auto t = b.is_object() ? b.find("componentType") : b.end();
        if (t != b.end() &&
            !(t->is_string() && (*t == "UNSIGNED_BYTE" || *t == "UNSIGNED_SHORT" || *t == "UNSIGNED_INT")))
            fail(ft.file, FeatureTable::path("BATCH_ID.componentType"),
                 "must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
        p.batchIds = draco->values<uint32_t>("BATCH_ID", 1);
    } else {
        p.batchIds = readBatchIds(ft, n);
    }
    p.hasBatchIds = ft.find("BATCH_ID") != nullptr;
}

// The batch table as a store: BATCH_LENGTH rows with BATCH_ID, else one per point. Draco-compressed properties are
// decoded into its binary first.
ref_ptr<const PropertyStore> batchStore(const std::string& file, const Sections& s, PntsDraco* draco, uint32_t rows,
                                        std::vector<std::string>& warnings) {
    std::string json;
    std::vector<unsigned char> binary;
    if (draco && draco->batchTable(s.batchJson, s.batchBinary, json, binary))
        return readBatchTable(file, Bytes{reinterpret_cast<const unsigned char*>(json.data()), json.size()},
                              Bytes{binary.data(), binary.size()}, rows, warnings);
    return readBatchTable(file, s.batchJson, s.batchBinary, rows, warnings);
}

// BATCH_ID: an attribute set over the batch table (BATCH_LENGTH rows); without, a table of a row per point is an
// implicit set. Null when there is neither.
ref_ptr<const MeshFeatures> features(const std::string& file, const Sections& s, PntsDraco* draco, uint32_t n,
                                     Points& p, std::vector<std::string>& warnings) {
    uint32_t rows = n;
    if (p.hasBatchIds) {
        uint64_t seen = 0;
        for (uint32_t id : p.batchIds) seen = std::max(seen, uint64_t(id) + 1);
        const std::optional<uint32_t> length = s.featureTable.globalUint("BATCH_LENGTH");
        if (!length)
            warnings.push_back(FeatureTable::path("BATCH_LENGTH") + ": missing (BATCH_ID needs it); " + str(seen) +
                               ", from the ids, is used");
        rows = length ? *length : uint32_t(std::min<uint64_t>(seen, UINT32_MAX));
        if (seen > rows)
            warnings.push_back(FeatureTable::path("BATCH_ID") + ": ids up to " + str(seen - 1) + " past BATCH_LENGTH " +
                               str(rows) + " read as no properties");
    }
    ref_ptr<const PropertyStore> store = batchStore(file, s, draco, rows, warnings);
    if (!store && !p.hasBatchIds) return nullptr;
    FeatureIdSet set;
    set.source = p.hasBatchIds ? FeatureIdSet::Source::Attribute : FeatureIdSet::Source::Implicit;
    set.featureCount = rows;
    set.propertyTable = store ? 0 : -1;
    set.ids = std::move(p.batchIds);
    auto f = make<MeshFeatures>();
    f->sets.push_back(std::move(set));
    f->store = store;
    return f;
}

// The material: per-point colours over white (else CONSTANT_RGBA, else the default), lit only with normals, and
// blended when some alpha is below 1.
ref_ptr<Material> material(const Points& p) {
    auto m = make<Material>();
    if (!p.colors.empty()) m->baseColor = vec4(1.0f);
    if (p.constant) m->baseColor = *p.constant;
    m->unlit = p.normals.empty();
    bool translucent = m->baseColor.a < 1.0f;
    for (const vec4& c : p.colors) translucent = translucent || c.a < 1.0f;
    m->blend = translucent;
    return m;
}

}  // namespace

ref_ptr<Node> readPnts(const std::string& file, const unsigned char* data, size_t size,
                       std::vector<std::string>& warnings) {
    checkHeader(file, "", data, size, "pnts", 28);
    const Sections s = readSections(file, data, size, 28);
    const FeatureTable& ft = s.featureTable;
    const std::optional<uint32_t> length = ft.globalUint("POINTS_LENGTH");
    if (!length) fail(file, FeatureTable::path("POINTS_LENGTH"), "is missing (required)");
    const uint32_t n = *length;
    if (n == 0) fail(file, FeatureTable::path("POINTS_LENGTH"), "is 0: no points");

    // Every per-point array is checked to hold POINTS_LENGTH elements (or decoded to as many) before it is read.
    const std::unique_ptr<PntsDraco> draco = PntsDraco::decode(ft, n, warnings);
    Points p;
    readPositions(ft, n, draco.get(), p);
    readColors(ft, n, draco.get(), p);
    readNormals(ft, n, draco.get(), p);
    readBatch(ft, n, draco.get(), p);
    const ref_ptr<const MeshFeatures> f = features(file, s, draco.get(), n, p, warnings);

    auto mesh = make<Mesh>();
    ref_ptr<Material> mat = material(p);
    try {
        mesh->setPoints(std::move(p.positions), std::move(p.colors), std::move(p.normals));
        if (f) mesh->setFeatures(f);
    } catch (const std::invalid_argument& e) {
        fail(file, "featureTable", e.what());  // the arrays were made to agree: not expected
    }
    mesh->setSource(MeshSource{file});
    auto t = make<Transform>(glm::translate(dmat4(1.0), p.origin));
    t->addChild(make<Geometry>(mesh, mat));
    return t;
}

}  // namespace sg::tiles
