// KHR_draco_mesh_compression through Debian's libdraco: each compressed primitive becomes plain accessors in one
// buffer added to the model, before validate() and convert() see it.
#include "loaders/gltf/internal/GltfDraco.h"

#include "loaders/gltf/internal/GltfDetail.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <string_view>

namespace sg::gltf {
namespace {

// An integer member of a JSON object, or -1 when absent or not a non-negative integer.
int intMember(const tinygltf::Value& obj, const char* key) {
    if (!obj.Has(key)) return -1;
    const tinygltf::Value& v = obj.Get(key);
    if (!v.IsNumber()) return -1;
    const double d = v.GetNumberAsDouble();
    return d >= 0.0 && d <= 2147483647.0 && d == std::floor(d) ? int(d) : -1;
}

// Values of `a` for points 0..n-1 as `comps` components of T each, into `out`. False when a value cannot be
// represented (draco's ConvertValue refuses out-of-range integers, NaN to integer, ...) or an index is bad.
template <typename T>
bool copyValues(const draco::PointAttribute& a, size_t n, int comps, unsigned char* out) {
    if (!a.is_mapping_identity() && a.indices_map_size() < n) return false;
    T v[4];
    for (size_t i = 0; i < n; ++i) {
        const draco::AttributeValueIndex avi = a.mapped_index(draco::PointIndex(uint32_t(i)));
        if (avi.value() >= a.size() || !a.ConvertValue<T>(avi, int8_t(comps), v)) return false;
        std::memcpy(out + i * size_t(comps) * sizeof(T), v, size_t(comps) * sizeof(T));
    }
    return true;
}

bool copyAttribute(const draco::PointAttribute& a, const tinygltf::Accessor& acc, size_t n, unsigned char* out) {
    const int comps = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return copyValues<float>(a, n, comps, out);
        case TINYGLTF_COMPONENT_TYPE_BYTE: return copyValues<int8_t>(a, n, comps, out);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return copyValues<uint8_t>(a, n, comps, out);
        case TINYGLTF_COMPONENT_TYPE_SHORT: return copyValues<int16_t>(a, n, comps, out);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return copyValues<uint16_t>(a, n, comps, out);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return copyValues<uint32_t>(a, n, comps, out);
        default: return false;
    }
}

class Decoder {
public:
    Decoder(const std::string& file, tinygltf::Model& m) : file_(file), m_(m), buffer_(int(m.buffers.size())) {}

    void primitive(size_t mesh, size_t prim) {
        tinygltf::Primitive& p = m_.meshes[mesh].primitives[prim];
        const auto ext = p.extensions.find(kDraco);
        if (ext == p.extensions.end()) return;
        path_ = at(at("meshes", mesh) + ".primitives", prim) + ".extensions." + kDraco;
        const tinygltf::Value& x = ext->second;
        if (!x.IsObject()) fail(file_, path_, "must be an object");
        const int view = intMember(x, "bufferView");
        if (view < 0 || size_t(view) >= m_.bufferViews.size())
            fail(file_, path_ + ".bufferView",
                 "must name one of the " + std::to_string(m_.bufferViews.size()) + " buffer views");
        const tinygltf::Value* attrs = x.Has("attributes") ? &x.Get("attributes") : nullptr;
        if (!attrs || !attrs->IsObject()) fail(file_, path_ + ".attributes", "must be an object");
        if (p.mode >= TINYGLTF_MODE_LINE && p.mode <= TINYGLTF_MODE_LINE_STRIP)
            fail(file_, path_,
                 "mode " + std::to_string(p.mode) + " is lines: " + kDraco + " compresses triangles and points only");
        if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_POINTS)
            fail(file_, path_, "mode " + std::to_string(p.mode) + " is not triangles or points");

        view_ = view;
        const draco::PointCloud& g = decoded(view, p.mode == TINYGLTF_MODE_TRIANGLES);
        const size_t points = g.num_points();
        // A Draco point cloud is its points in order: an indices accessor would have nothing to decode into it.
        if (p.mode == TINYGLTF_MODE_POINTS && p.indices >= 0)
            fail(file_, path_,
                 "a point cloud has no indices, yet the primitive names accessor " + std::to_string(p.indices) +
                     " for them");
        for (const std::string& name : attrs->Keys()) {
            const int id = intMember(*attrs, name.c_str());
            const std::string ap = path_ + ".attributes." + name;
            if (id < 0) fail(file_, ap, "must be a Draco attribute id");
            const auto target = p.attributes.find(name);
            if (target == p.attributes.end())
                fail(file_, ap, "the primitive has no attribute " + name + " for it to decode into");
            const draco::PointAttribute* a = g.GetAttributeByUniqueId(uint32_t(id));
            if (!a) fail(file_, ap, "the Draco stream has no attribute with id " + std::to_string(id));
            target->second =
                rewrite(target->second, ap, id, points, [&](const tinygltf::Accessor& acc, unsigned char* out) {
                    const int comps = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
                    if (a->num_components() != comps)
                        fail(file_, ap,
                             "Draco attribute " + std::to_string(id) + " has " + std::to_string(a->num_components()) +
                                 " components, the accessor " + std::to_string(comps));
                    if (!copyAttribute(*a, acc, points, out))
                        fail(file_, ap,
                             "Draco attribute " + std::to_string(id) +
                                 " does not convert to the accessor's componentType " +
                                 std::to_string(acc.componentType));
                });
        }
        if (p.mode == TINYGLTF_MODE_TRIANGLES) {
            const auto& mesh3 = static_cast<const draco::Mesh&>(g);
            const size_t faces = mesh3.num_faces();
            if (p.indices < 0) {  // the stream holds indexed triangles: give them an accessor
                tinygltf::Accessor acc;
                acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
                acc.type = TINYGLTF_TYPE_SCALAR;
                acc.count = faces * 3;
                m_.accessors.push_back(acc);
                p.indices = int(m_.accessors.size() - 1);
            }
            p.indices =
                rewrite(p.indices, path_, -1, faces * 3, [&](const tinygltf::Accessor& acc, unsigned char* out) {
                    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
                    const uint64_t max = size == 1 ? 0xffu : size == 2 ? 0xffffu : 0xffffffffu;
                    if (acc.type != TINYGLTF_TYPE_SCALAR ||
                        (acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                         acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                         acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
                        fail(file_, path_, "the indices accessor is not SCALAR of an unsigned integer type");
                    for (size_t f = 0; f < faces; ++f)
                        for (int k = 0; k < 3; ++k) {
                            const uint32_t v = mesh3.face(draco::FaceIndex(uint32_t(f)))[k].value();
                            if (v >= points || v > max)
                                fail(file_, path_,
                                     "decoded triangle " + std::to_string(f) + " has index " + std::to_string(v) +
                                         " past its " + std::to_string(points) + " points or its componentType");
                            unsigned char* o = out + (f * 3 + size_t(k)) * size_t(size);
                            for (int b = 0; b < size; ++b) o[b] = uint8_t(v >> (8 * b));  // glTF is little-endian
                        }
                });
        }
        p.extensions.erase(ext);
    }

    // Adds the buffer all decoded views live in.
    void finish() {
        if (data_.empty()) return;
        tinygltf::Buffer b;
        b.name = "decoded Draco";
        b.data = std::move(data_);
        m_.buffers.push_back(std::move(b));
    }

private:
    // The stream in buffer view `view`, decoded once (primitives may share one); a triangle mesh when `triangles`
    // (the cache is keyed by both, so a view read as both kinds is refused rather than cast).
    const draco::PointCloud& decoded(int view, bool triangles) {
        auto found = decoded_.find({view, triangles});
        if (found != decoded_.end()) return *found->second;
        const tinygltf::BufferView& v = m_.bufferViews[size_t(view)];
        if (v.buffer < 0 || size_t(v.buffer) >= m_.buffers.size())
            fail(file_, path_ + ".bufferView", "buffer view " + std::to_string(view) + " names no buffer");
        const std::vector<unsigned char>& data = m_.buffers[size_t(v.buffer)].data;
        if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset)
            fail(file_, path_ + ".bufferView",
                 "buffer view " + std::to_string(view) + " is past the end of its buffer");
        draco::DecoderBuffer in;
        in.Init(reinterpret_cast<const char*>(data.data() + v.byteOffset), v.byteLength);
        std::unique_ptr<draco::PointCloud> out;
        try {
            const auto type = draco::Decoder::GetEncodedGeometryType(&in);
            if (!type.ok()) fail(file_, path_, "not a Draco stream: " + type.status().error_msg_string());
            if ((type.value() == draco::TRIANGULAR_MESH) != triangles)
                fail(file_, path_,
                     std::string("the Draco stream holds ") +
                         (type.value() == draco::TRIANGULAR_MESH ? "a triangle mesh" : "no triangle mesh") +
                         ", the primitive's mode is " + (triangles ? "triangles" : "points"));
            draco::Decoder d;
            if (triangles) {
                auto r = d.DecodeMeshFromBuffer(&in);
                if (!r.ok()) fail(file_, path_, "Draco cannot decode it: " + r.status().error_msg_string());
                out = std::move(r).value();
            } else {
                auto r = d.DecodePointCloudFromBuffer(&in);
                if (!r.ok()) fail(file_, path_, "Draco cannot decode it: " + r.status().error_msg_string());
                out = std::move(r).value();
            }
        } catch (const std::bad_alloc&) {
            fail(file_, path_, "out of memory while decoding (the stream claims too much)");
        } catch (const std::length_error&) {
            fail(file_, path_, "the stream claims more data than can be held");
        }
        if (!out) fail(file_, path_, "Draco decoded nothing");
        return *(decoded_[{view, triangles}] = std::move(out));
    }

    // Points accessor `index` (which must declare `count` elements) at a new buffer view that `fill` writes, and
    // returns it. Accessors of Draco primitives have no data of their own; the one an encoder shares between
    // primitives of one stream is decoded once, and one shared by two streams or attributes is refused.
    template <typename Fill>
    int rewrite(int index, const std::string& where, int id, size_t count, Fill fill) {
        const std::string what = id < 0 ? "the indices accessor " : "accessor ";
        if (index < 0 || size_t(index) >= m_.accessors.size())
            fail(file_, where, what + std::to_string(index) + " does not exist");
        const auto source = std::make_pair(view_, id);
        const auto known = decodedFrom_.find(index);
        if (known != decodedFrom_.end()) {
            if (known->second != source)
                fail(file_, where,
                     what + std::to_string(index) + " is also decoded from another Draco stream or attribute");
            return index;
        }
        tinygltf::Accessor& acc = m_.accessors[size_t(index)];
        const int comp = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
        const int num = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
        if (comp <= 0 || num <= 0) fail(file_, where, what + std::to_string(index) + " has an unknown type");
        if (acc.count != count)
            fail(file_, where,
                 what + std::to_string(index) + " declares " + std::to_string(acc.count) +
                     " elements, the Draco stream decodes " + std::to_string(count));
        const size_t bytes = count * size_t(comp) * size_t(num);
        if (bytes > kMaxDracoBytes - data_.size())
            fail(file_, where,
                 "decoded data would exceed " + std::to_string(kMaxDracoBytes >> 20) + " MiB for the file");
        const size_t offset = data_.size();
        data_.resize(offset + ((bytes + 3) & ~size_t(3)), 0);
        fill(acc, data_.data() + offset);
        tinygltf::BufferView v;
        v.buffer = buffer_;
        v.byteOffset = offset;
        v.byteLength = bytes;
        m_.bufferViews.push_back(v);
        acc.bufferView = int(m_.bufferViews.size() - 1);
        acc.byteOffset = 0;
        acc.sparse.isSparse = false;
        decodedFrom_[index] = source;
        return index;
    }

    const std::string& file_;
    tinygltf::Model& m_;
    const int buffer_;
    std::string path_;  // the primitive's extension being decoded
    int view_ = -1;     // and its buffer view
    std::vector<unsigned char> data_;
    std::map<std::pair<int, bool>, std::unique_ptr<draco::PointCloud>> decoded_;
    std::map<int, std::pair<int, int>> decodedFrom_;  // accessor -> (buffer view, attribute id or -1)
};

}  // namespace

std::vector<unsigned char> dracoIndicesForTinygltf(const unsigned char* data, size_t size, bool binary) {
    size_t jsonAt = 0, jsonLen = size;
    if (binary) {  // prevalidate() has checked the header and the chunk lengths
        jsonAt = 20;
        jsonLen = size_t(data[12]) | size_t(data[13]) << 8 | size_t(data[14]) << 16 | size_t(data[15]) << 24;
    }
    const std::string_view json0(reinterpret_cast<const char*>(data) + jsonAt, jsonLen);
    if (json0.find(kDraco) == std::string_view::npos) return {};  // most files: nothing copied
    std::string text(json0);
    while (!text.empty() && (text.back() == '\0' || text.back() == ' ')) text.pop_back();  // GLB padding
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j["meshes"].is_array() || !j["accessors"].is_array()) return {};
    nlohmann::json& accessors = j["accessors"];
    const size_t views = j["bufferViews"].is_array() ? j["bufferViews"].size() : 0;
    bool changed = false;
    for (const auto& mesh : j["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (const auto& p : mesh["primitives"]) {
            if (!p.is_object() || !p.contains("indices") || !p["indices"].is_number_unsigned()) continue;
            const auto ext = p.find("extensions");
            if (ext == p.end() || !ext->is_object() || !ext->contains(kDraco)) continue;
            const size_t i = p["indices"].get<size_t>();
            if (i >= accessors.size() || !accessors[i].is_object() || accessors[i].contains("bufferView") || views == 0)
                continue;
            // The extension's view when it names one; else any, for decodeDraco() to say what is wrong.
            const nlohmann::json& x = (*ext)[kDraco];
            const bool named = x.is_object() && x.contains("bufferView") && x["bufferView"].is_number_unsigned() &&
                               x["bufferView"].get<size_t>() < views;
            accessors[i]["bufferView"] = named ? x["bufferView"].get<size_t>() : size_t(0);
            changed = true;
        }
    }
    if (!changed) return {};
    std::string json = j.dump();
    if (!binary) return std::vector<unsigned char>(json.begin(), json.end());
    json.resize((json.size() + 3) & ~size_t(3), ' ');
    const size_t length = size_t(data[8]) | size_t(data[9]) << 8 | size_t(data[10]) << 16 | size_t(data[11]) << 24;
    const size_t rest = length - (jsonAt + jsonLen);  // the chunks after JSON
    std::vector<unsigned char> out(data, data + 12);
    const auto le32 = [&](size_t v) {
        for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
    };
    le32(json.size());
    out.insert(out.end(), data + 16, data + 20);  // "JSON"
    out.insert(out.end(), json.begin(), json.end());
    out.insert(out.end(), data + jsonAt + jsonLen, data + length);
    const size_t total = 12 + 8 + json.size() + rest;
    for (int k = 0; k < 4; ++k) out[8 + size_t(k)] = uint8_t(total >> (8 * k));
    return out;
}

void decodeDraco(const std::string& file, tinygltf::Model& model) {
    Decoder d(file, model);
    try {
        for (size_t i = 0; i < model.meshes.size(); ++i)
            for (size_t j = 0; j < model.meshes[i].primitives.size(); ++j) d.primitive(i, j);
    } catch (const std::bad_alloc&) {
        fail(file, "", "out of memory while decoding Draco streams");
    }
    d.finish();
}

}  // namespace sg::gltf
