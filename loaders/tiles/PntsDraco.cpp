// 3DTILES_draco_point_compression: the Draco stream in a point cloud's feature table binary, decoded with libdraco
// (as loaders/gltf/GltfDraco.cpp decodes glTF's). Each attribute is read through Draco's own conversion, so that
// quantized positions and octahedral normals come out as floats; a value it cannot represent is an error.
#include "loaders/gltf/internal/GltfDetail.h"   // checkJsonDepth, fail
#include "loaders/tiles/internal/BatchTable.h"  // batch::componentOf
#include "loaders/tiles/internal/Pnts.h"

#include <draco/compression/decode.h>
#include <draco/point_cloud/point_cloud.h>

#include <map>
#include <new>
#include <set>
#include <stdexcept>

namespace sg::tiles {

using gltf::fail;
using json = nlohmann::json;

namespace {

constexpr const char* kExtension = "3DTILES_draco_point_compression";
const std::string kPath = std::string("featureTable.extensions.") + kExtension;

// An attribute's values for points 0..n-1, `comps` of T each, appended to `out`; false when Draco cannot convert one.
template <class T>
bool convert(const draco::PointAttribute& a, size_t n, int comps, std::vector<T>& out) {
    if (!a.is_mapping_identity() && a.indices_map_size() < n) return false;
    T v[4];
    for (size_t i = 0; i < n; ++i) {
        const draco::AttributeValueIndex avi = a.mapped_index(draco::PointIndex(uint32_t(i)));
        if (avi.value() >= a.size() || !a.ConvertValue<T>(avi, int8_t(comps), v)) return false;
        out.insert(out.end(), v, v + comps);
    }
    return true;
}

// The same as bytes of the batch table's component type, appended to `out` (the format is little-endian, as the
// supported hosts are).
template <class T>
bool appendAs(const draco::PointAttribute& a, size_t n, int comps, std::vector<unsigned char>& out) {
    std::vector<T> v;
    if (!convert(a, n, comps, v)) return false;
    const auto* b = reinterpret_cast<const unsigned char*>(v.data());
    out.insert(out.end(), b, b + v.size() * sizeof(T));
    return true;
}

bool appendValues(const draco::PointAttribute& a, size_t n, int comps, ComponentType c,
                  std::vector<unsigned char>& out) {
    switch (c) {
        case ComponentType::Int8: return appendAs<int8_t>(a, n, comps, out);
        case ComponentType::UInt8: return appendAs<uint8_t>(a, n, comps, out);
        case ComponentType::Int16: return appendAs<int16_t>(a, n, comps, out);
        case ComponentType::UInt16: return appendAs<uint16_t>(a, n, comps, out);
        case ComponentType::Int32: return appendAs<int32_t>(a, n, comps, out);
        case ComponentType::UInt32: return appendAs<uint32_t>(a, n, comps, out);
        case ComponentType::Float32: return appendAs<float>(a, n, comps, out);
        case ComponentType::Float64: return appendAs<double>(a, n, comps, out);
        default: return false;
    }
}

// The stream's bytes: byteOffset and byteLength inside the feature table binary.
Bytes streamBytes(const FeatureTable& ft, const json& x) {
    uint64_t v[2];
    const char* names[2] = {"byteOffset", "byteLength"};
    for (int k = 0; k < 2; ++k) {
        const auto it = x.find(names[k]);
        if (it == x.end() || !it->is_number_unsigned())
            fail(ft.file, kPath + "." + names[k], "is missing or not a non-negative integer");
        v[k] = it->get<uint64_t>();
    }
    if (v[0] > ft.binary.size || v[1] > ft.binary.size - v[0])
        fail(ft.file, kPath + ".byteLength",
             "byteOffset " + std::to_string(v[0]) + " + byteLength " + std::to_string(v[1]) +
                 " is past the end of the feature table binary (" + std::to_string(ft.binary.size) + " bytes)");
    return Bytes{ft.binary.data + v[0], size_t(v[1])};
}

std::unique_ptr<draco::PointCloud> decodeStream(const std::string& file, Bytes b) {
    draco::DecoderBuffer in;
    in.Init(reinterpret_cast<const char*>(b.data), b.size);
    try {
        const auto type = draco::Decoder::GetEncodedGeometryType(&in);
        if (!type.ok()) fail(file, kPath, "not a Draco stream: " + type.status().error_msg_string());
        draco::Decoder d;
        auto r = d.DecodePointCloudFromBuffer(&in);  // a triangle mesh's stream is read as its points
        if (!r.ok()) fail(file, kPath, "Draco cannot decode it: " + r.status().error_msg_string());
        if (!r.value()) fail(file, kPath, "Draco decoded nothing");
        return std::move(r).value();
    } catch (const std::bad_alloc&) {
        fail(file, kPath, "out of memory while decoding (the stream claims too much)");
    } catch (const std::length_error&) {
        fail(file, kPath, "the stream claims more data than can be held");
    }
}

// The attribute `properties`[name] names, its id not used before (ids are unique across both tables).
const draco::PointAttribute* attribute(const std::string& file, const draco::PointCloud& g, const json& id,
                                       const std::string& path, std::set<uint64_t>& used) {
    if (!id.is_number_unsigned()) fail(file, path, "must be a Draco attribute id (a non-negative integer)");
    const uint64_t k = id.get<uint64_t>();
    if (!used.insert(k).second) fail(file, path, "Draco attribute id " + std::to_string(k) + " is named twice");
    const draco::PointAttribute* a = k <= UINT32_MAX ? g.GetAttributeByUniqueId(uint32_t(k)) : nullptr;
    if (!a) fail(file, path, "the Draco stream has no attribute with id " + std::to_string(k));
    return a;
}

}  // namespace

struct PntsDraco::Impl {
    const std::string& file;
    std::unique_ptr<draco::PointCloud> cloud;
    std::map<std::string, const draco::PointAttribute*> semantics;
    std::set<uint64_t> used;
};

PntsDraco::PntsDraco(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
PntsDraco::~PntsDraco() = default;

std::unique_ptr<PntsDraco> PntsDraco::decode(const FeatureTable& ft, uint32_t points,
                                             std::vector<std::string>& warnings) {
    const json* ext = ft.find("extensions");
    if (!ext || !ext->is_object() || !ext->contains(kExtension)) return nullptr;
    const json& x = (*ext)[kExtension];
    if (!x.is_object()) fail(ft.file, kPath, "must be an object");
    const auto props = x.find("properties");
    if (props == x.end() || !props->is_object()) fail(ft.file, kPath + ".properties", "must be an object");

    auto impl = std::make_unique<Impl>(Impl{ft.file, decodeStream(ft.file, streamBytes(ft, x)), {}, {}});
    const uint32_t decoded = impl->cloud->num_points();
    if (decoded != points)
        fail(ft.file, kPath,
             "the Draco stream holds " + std::to_string(decoded) + " points, POINTS_LENGTH is " +
                 std::to_string(points));
    static const std::set<std::string> allowed = {"POSITION", "RGBA", "RGB", "NORMAL", "BATCH_ID"};
    for (const auto& [name, id] : props->items()) {
        const std::string path = kPath + ".properties." + name;
        if (!allowed.count(name)) {
            warnings.push_back(path + ": not a semantic the extension compresses; left out");
            continue;
        }
        if (!ft.find(name.c_str())) fail(ft.file, path, "the feature table has no " + name + " semantic");
        impl->semantics[name] = attribute(ft.file, *impl->cloud, id, path, impl->used);
    }
    return std::unique_ptr<PntsDraco>(new PntsDraco(std::move(impl)));
}

bool PntsDraco::has(const std::string& semantic) const { return impl_->semantics.count(semantic) != 0; }

template <class T>
std::vector<T> PntsDraco::values(const std::string& semantic, int components) const {
    const draco::PointAttribute& a = *impl_->semantics.at(semantic);
    const std::string path = kPath + ".properties." + semantic;
    if (a.num_components() != components)
        fail(impl_->file, path,
             "the Draco attribute has " + std::to_string(int(a.num_components())) + " components, " + semantic +
                 " has " + std::to_string(components));
    std::vector<T> out;
    out.reserve(size_t(impl_->cloud->num_points()) * size_t(components));
    if (!convert(a, impl_->cloud->num_points(), components, out))
        fail(impl_->file, path, "the Draco attribute's values do not convert to " + semantic + "'s type");
    return out;
}
template std::vector<float> PntsDraco::values<float>(const std::string&, int) const;
template std::vector<uint8_t> PntsDraco::values<uint8_t>(const std::string&, int) const;
template std::vector<uint32_t> PntsDraco::values<uint32_t>(const std::string&, int) const;

bool PntsDraco::batchTable(Bytes jsonBytes, Bytes binary, std::string& jsonOut, std::vector<unsigned char>& binaryOut) {
    const std::string& file = impl_->file;
    size_t n = jsonBytes.size;
    while (n > 0 && (jsonBytes.data[n - 1] == ' ' || jsonBytes.data[n - 1] == '\0')) --n;  // padding
    if (n == 0) return false;
    nlohmann::ordered_json j;
    try {
        gltf::checkJsonDepth(file, jsonBytes.data, n);
        j = nlohmann::ordered_json::parse(jsonBytes.data, jsonBytes.data + n);
    } catch (const nlohmann::ordered_json::exception& e) {
        fail(file, "batchTable", std::string("JSON: ") + e.what());
    }
    if (!j.is_object() || !j.contains("extensions") || !j["extensions"].is_object() ||
        !j["extensions"].contains(kExtension))
        return false;
    const std::string path = std::string("batchTable.extensions.") + kExtension;
    const auto& x = j["extensions"][kExtension];
    const auto found = x.is_object() ? x.find("properties") : x.end();
    if (found == x.end() || !found->is_object()) fail(file, path + ".properties", "must be an object");
    const auto& props = *found;

    std::vector<unsigned char> out(binary.data, binary.data + binary.size);
    const size_t points = impl_->cloud->num_points();
    for (const auto& [name, id] : props.items()) {
        const std::string pp = path + ".properties." + name;
        if (!j.contains(name) || !j[name].is_object())
            fail(file, pp, "the batch table has no binary property " + name + " for it to decode into");
        auto& ref = j[name];
        const ComponentType c = ref.contains("componentType") && ref["componentType"].is_string()
                                    ? batch::componentOf(ref["componentType"].get<std::string>())
                                    : ComponentType::None;
        const std::string type = ref.contains("type") && ref["type"].is_string() ? ref["type"].get<std::string>() : "";
        const int comps = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 0;
        if (c == ComponentType::None || comps == 0)
            fail(file, "batchTable." + name, "needs a known componentType and a type SCALAR or VEC2..VEC4");
        const draco::PointAttribute* a = attribute(file, *impl_->cloud, id, pp, impl_->used);
        if (a->num_components() != comps)
            fail(file, pp,
                 "the Draco attribute has " + std::to_string(int(a->num_components())) + " components, " + type +
                     " has " + std::to_string(comps));
        while (out.size() % 8) out.push_back(0);  // each property aligned to its component size (8 covers all)
        ref["byteOffset"] = out.size();
        if (!appendValues(*a, points, comps, c, out))
            fail(file, pp, "the Draco attribute's values do not convert to " + ref["componentType"].get<std::string>());
    }
    j["extensions"].erase(kExtension);
    if (j["extensions"].empty()) j.erase("extensions");
    jsonOut = j.dump();
    binaryOut = std::move(out);
    return true;
}

}  // namespace sg::tiles
