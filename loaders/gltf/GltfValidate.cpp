// Validation the glTF loader does itself: on the raw bytes before tinygltf, and on tinygltf's model after.
#include "loaders/gltf/internal/GltfDetail.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

namespace sg::gltf {

bool supportedExtension(const std::string& name) {
    static const std::set<std::string> supported{
        "KHR_materials_unlit",        kInstancing,   "KHR_texture_transform",   "KHR_materials_emissive_strength",
        "KHR_lights_punctual",        kQuantization, "EXT_meshopt_compression", "KHR_meshopt_compression",
        "KHR_draco_mesh_compression", kMeshFeatures, kStructuralMetadata,       kInstanceFeatures,
        "CESIUM_primitive_outline"};
    return supported.count(name) != 0 || name == kAnimationPointer;
}

bool shadingOnlyExtension(const std::string& name) {
    // Materials approximated (GltfMaterials.cpp: specular-glossiness, WebGL techniques) or drawn with their core
    // metallic-roughness part; textures only in KTX2 or WebP (not decoded) drawn untextured.
    static const std::set<std::string> shading{"KHR_materials_pbrSpecularGlossiness",
                                               "KHR_techniques_webgl",
                                               "KHR_technique_webgl",
                                               "KHR_materials_clearcoat",
                                               "KHR_materials_sheen",
                                               "KHR_materials_specular",
                                               "KHR_materials_ior",
                                               "KHR_materials_transmission",
                                               "KHR_materials_volume",
                                               "KHR_materials_iridescence",
                                               "KHR_materials_anisotropy",
                                               "KHR_materials_dispersion",
                                               "KHR_texture_basisu",
                                               "EXT_texture_webp"};
    return shading.count(name) != 0;
}

std::string at(const std::string& array, size_t i) { return array + "[" + std::to_string(i) + "]"; }

void fail(const std::string& file, const std::string& path, const std::string& reason) {
    throw LoadError(file, path, reason);
}

// Nesting depth of JSON text, strings skipped; stops counting at the first excess.
void checkJsonDepth(const std::string& file, const unsigned char* p, size_t n) {
    int depth = 0;
    bool inString = false;
    for (size_t i = 0; i < n; ++i) {
        const unsigned char c = p[i];
        if (inString) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                fail(file, "",
                     "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels at byte " +
                         std::to_string(i));
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

const char* typeName(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return "SCALAR";
        case TINYGLTF_TYPE_VEC2: return "VEC2";
        case TINYGLTF_TYPE_VEC3: return "VEC3";
        case TINYGLTF_TYPE_VEC4: return "VEC4";
        case TINYGLTF_TYPE_MAT2: return "MAT2";
        case TINYGLTF_TYPE_MAT3: return "MAT3";
        case TINYGLTF_TYPE_MAT4: return "MAT4";
        default: return "an unknown type";
    }
}

namespace {

uint32_t le32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// Checks the index `i` found at `path` against an array of `n` elements called `what`.
struct Checker {
    const std::string& file;
    const tinygltf::Model& m;

    void index(const std::string& path, int i, size_t n, const char* what, bool optional = false) const {
        if (optional && i == -1) return;
        if (i < 0 || size_t(i) >= n)
            fail(file, path,
                 std::string(what) + " " + std::to_string(i) + " does not exist (" + std::to_string(n) + " " + what +
                     (n == 1                           ? ""
                      : std::strcmp(what, "mesh") == 0 ? "es"
                                                       : "s") +
                     ")");
    }
    // `limit`: the largest magnitude allowed (values stored as float are held to float's range).
    void finite(const std::string& path, const std::vector<double>& v, size_t wantSize,
                double limit = std::numeric_limits<double>::max()) const {
        if (v.empty()) return;
        if (v.size() != wantSize)
            fail(file, path, "has " + std::to_string(v.size()) + " numbers, needs " + std::to_string(wantSize));
        for (size_t k = 0; k < v.size(); ++k) {
            if (!std::isfinite(v[k]))
                fail(file, path, "element " + std::to_string(k) + " is not finite (" + std::to_string(v[k]) + ")");
            if (std::abs(v[k]) > limit) fail(file, path, "element " + std::to_string(k) + " is out of float range");
        }
    }

    void extensions() const {
        for (size_t i = 0; i < m.extensionsRequired.size(); ++i)
            if (!supportedExtension(m.extensionsRequired[i]) && !shadingOnlyExtension(m.extensionsRequired[i]))
                fail(file, at("extensionsRequired", i),
                     "extension '" + m.extensionsRequired[i] + "' is required but not supported");
    }

    void bufferViews() const {
        for (size_t i = 0; i < m.bufferViews.size(); ++i) {
            const tinygltf::BufferView& v = m.bufferViews[i];
            const std::string path = at("bufferViews", i);
            index(path + ".buffer", v.buffer, m.buffers.size(), "buffer");
            const size_t have = m.buffers[size_t(v.buffer)].data.size();
            if (v.byteOffset > have || v.byteLength > have - v.byteOffset)
                fail(file, path,
                     "byteOffset " + std::to_string(v.byteOffset) + " + byteLength " + std::to_string(v.byteLength) +
                         " is past the end of buffer " + std::to_string(v.buffer) + " (" + std::to_string(have) +
                         " bytes)");
            if (v.byteStride != 0 && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4 != 0))
                fail(file, path + ".byteStride",
                     "byteStride " + std::to_string(v.byteStride) + " is not a multiple of 4 in [4, 252]");
        }
    }

    void accessors() const {
        size_t sparseBytes = 0;
        for (size_t i = 0; i < m.accessors.size(); ++i) {
            const tinygltf::Accessor& a = m.accessors[i];
            const std::string path = at("accessors", i);
            const int comp = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
            const int num = tinygltf::GetNumComponentsInType(uint32_t(a.type));
            if (comp <= 0)
                fail(file, path + ".componentType", "unknown componentType " + std::to_string(a.componentType));
            if (num <= 0) continue;  // kUnknownType: not read (undoNormalizing), any use refused by its type
            if (a.count < 1) fail(file, path + ".count", "count " + std::to_string(a.count) + " is below 1");
            if (a.sparse.isSparse) checkSparse(file, m, i, sparseBytes);
            if (a.bufferView == -1) {  // all zeros: no data in the file holds the count to a sane size
                if (a.count > kMaxZeroAccessor)
                    fail(file, path + ".count",
                         "count " + std::to_string(a.count) + " without a bufferView is above " +
                             std::to_string(kMaxZeroAccessor));
                continue;
            }
            index(path + ".bufferView", a.bufferView, m.bufferViews.size(), "bufferView");
            const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
            const size_t elem = size_t(comp) * size_t(num);
            const size_t stride = v.byteStride ? v.byteStride : elem;
            if (stride < elem)
                fail(file, path,
                     "element of " + std::to_string(elem) + " bytes is larger than bufferViews[" +
                         std::to_string(a.bufferView) + "].byteStride " + std::to_string(stride));
            // The last element must end inside the view (written to avoid overflow for huge counts).
            const size_t len = v.byteLength;
            if (a.byteOffset > len || elem > len - a.byteOffset || (a.count - 1) > (len - a.byteOffset - elem) / stride)
                fail(file, path,
                     "byteOffset " + std::to_string(a.byteOffset) + " + " + std::to_string(a.count) + " elements of " +
                         std::to_string(elem) + " bytes (stride " + std::to_string(stride) +
                         ") is past the end of bufferViews[" + std::to_string(a.bufferView) + "] (" +
                         std::to_string(len) + " bytes)");
        }
    }

    // `type` and the allowed component types of an attribute.
    void attribute(const std::string& path, int acc, int type, std::initializer_list<int> comps, int type2 = -1) const {
        index(path, acc, m.accessors.size(), "accessor");
        const tinygltf::Accessor& a = m.accessors[size_t(acc)];
        bool compOk = false;
        for (int c : comps) compOk |= a.componentType == c;
        if ((a.type != type && a.type != type2) || !compOk)
            fail(file, path,
                 std::string("accessor ") + std::to_string(acc) + " is " + typeName(a.type) + " of componentType " +
                     std::to_string(a.componentType) + ", needs " + typeName(type) +
                     (type2 >= 0 ? std::string(" or ") + typeName(type2) : std::string()) + " of componentType " +
                     std::to_string(*comps.begin()) + (comps.size() > 1 ? " (or normalized integers)" : ""));
    }

    // Integers that are not normalized make no unit vectors.
    void normalized(const std::string& path, int acc) const {
        const tinygltf::Accessor& a = m.accessors[size_t(acc)];
        if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized)
            fail(file, path,
                 "accessor " + std::to_string(acc) + " of componentType " + std::to_string(a.componentType) +
                     " must be normalized");
    }

    bool uses(const char* extension) const {
        auto has = [&](const std::vector<std::string>& v) {
            return std::find(v.begin(), v.end(), extension) != v.end();
        };
        return has(m.extensionsUsed) || has(m.extensionsRequired);
    }

    void meshes() const {
        // KHR_mesh_quantization: integer positions and texture coordinates (normalized or not), normalized
        // signed integer normals and tangents.
        const bool q = uses(kQuantization);
        const std::initializer_list<int> floatOnly{TINYGLTF_COMPONENT_TYPE_FLOAT};
        const std::initializer_list<int> signedInt{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                                                   TINYGLTF_COMPONENT_TYPE_SHORT};
        const std::initializer_list<int> anyInt{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
                                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
        for (size_t i = 0; i < m.meshes.size(); ++i) {
            for (size_t k = 0; k < m.meshes[i].primitives.size(); ++k) {
                const tinygltf::Primitive& p = m.meshes[i].primitives[k];
                const std::string path = at(at("meshes", i) + ".primitives", k);
                if (p.mode < 0 || p.mode > 6) fail(file, path + ".mode", "unknown mode " + std::to_string(p.mode));
                index(path + ".material", p.material, m.materials.size(), "material", true);
                auto pos = p.attributes.find("POSITION");
                if (pos == p.attributes.end()) continue;  // skipped with a warning by the conversion
                attribute(path + ".attributes.POSITION", pos->second, TINYGLTF_TYPE_VEC3, q ? anyInt : floatOnly);
                const size_t n = m.accessors[size_t(pos->second)].count;
                for (const auto& [name, acc] : p.attributes) {
                    const std::string ap = path + ".attributes." + name;
                    if (name == "NORMAL" || name == "TANGENT") {
                        attribute(ap, acc, name == "NORMAL" ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4,
                                  q ? signedInt : floatOnly);
                        normalized(ap, acc);
                    } else if (name == "TEXCOORD_0" || name == "TEXCOORD_1") {
                        attribute(ap, acc, TINYGLTF_TYPE_VEC2,
                                  q ? anyInt
                                    : std::initializer_list<int>{TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
                    } else if (name == "COLOR_0")
                        attribute(ap, acc, TINYGLTF_TYPE_VEC4,
                                  {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                                  TINYGLTF_TYPE_VEC3);
                    else
                        index(ap, acc, m.accessors.size(), "accessor");  // not read
                    if (m.accessors[size_t(acc)].count != n)
                        fail(file, ap,
                             "count " + std::to_string(m.accessors[size_t(acc)].count) +
                                 " differs from POSITION's count " + std::to_string(n));
                }
                // A TRIANGLES count that is not a multiple of 3 draws its whole triangles (GltfMeshes.cpp).
                if (p.indices != -1)
                    attribute(path + ".indices", p.indices, TINYGLTF_TYPE_SCALAR,
                              {TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE});
            }
        }
    }

    void materials() const {
        for (size_t i = 0; i < m.materials.size(); ++i) {
            const auto& pbr = m.materials[i].pbrMetallicRoughness;
            const std::string path = at("materials", i) + ".pbrMetallicRoughness";
            const tinygltf::Material& mat = m.materials[i];
            const std::string mp = at("materials", i);
            const double fmax = double(std::numeric_limits<float>::max());
            finite(path + ".baseColorFactor", pbr.baseColorFactor, 4, fmax);
            finite(mp + ".emissiveFactor", mat.emissiveFactor, 3, fmax);
            const std::pair<const char*, double> factors[] = {
                {".pbrMetallicRoughness.metallicFactor", pbr.metallicFactor},
                {".pbrMetallicRoughness.roughnessFactor", pbr.roughnessFactor},
                {".normalTexture.scale", mat.normalTexture.scale},
                {".occlusionTexture.strength", mat.occlusionTexture.strength},
                {".alphaCutoff", mat.alphaCutoff}};
            for (const auto& [name, v] : factors) finite(mp + name, {v}, 1, fmax);
            index(path + ".baseColorTexture.index", pbr.baseColorTexture.index, m.textures.size(), "texture", true);
            index(path + ".metallicRoughnessTexture.index", pbr.metallicRoughnessTexture.index, m.textures.size(),
                  "texture", true);
            index(mp + ".normalTexture.index", mat.normalTexture.index, m.textures.size(), "texture", true);
            index(mp + ".occlusionTexture.index", mat.occlusionTexture.index, m.textures.size(), "texture", true);
            index(mp + ".emissiveTexture.index", mat.emissiveTexture.index, m.textures.size(), "texture", true);
        }
        for (size_t i = 0; i < m.textures.size(); ++i) {
            index(at("textures", i) + ".source", m.textures[i].source, m.images.size(), "image", true);
            index(at("textures", i) + ".sampler", m.textures[i].sampler, m.samplers.size(), "sampler", true);
        }
        for (size_t i = 0; i < m.images.size(); ++i)
            index(at("images", i) + ".bufferView", m.images[i].bufferView, m.bufferViews.size(), "bufferView", true);
    }

    void cameras() const {
        for (size_t i = 0; i < m.cameras.size(); ++i) {
            const tinygltf::Camera& c = m.cameras[i];
            const std::string path = at("cameras", i);
            if (c.type == "perspective") {
                const auto& p = c.perspective;
                if (!(std::isfinite(p.znear) && p.znear > 0.0))
                    fail(file, path + ".perspective.znear", "znear " + std::to_string(p.znear) + " is not positive");
                if (!(std::isfinite(p.zfar) && (p.zfar == 0.0 || p.zfar > p.znear)))
                    fail(file, path + ".perspective.zfar", "zfar " + std::to_string(p.zfar) + " is not beyond znear");
                if (!(std::isfinite(p.aspectRatio) && p.aspectRatio >= 0.0))
                    fail(file, path + ".perspective.aspectRatio", "aspectRatio is negative or not finite");
            } else if (c.type == "orthographic") {
                const auto& o = c.orthographic;
                for (double v : {o.xmag, o.ymag, o.znear, o.zfar})
                    if (!std::isfinite(v)) fail(file, path + ".orthographic", "has a value that is not finite");
                if (!(o.zfar > o.znear)) fail(file, path + ".orthographic.zfar", "zfar is not beyond znear");
            } else {
                fail(file, path + ".type", "unknown camera type '" + c.type + "'");
            }
        }
    }

    // EXT_mesh_gpu_instancing on a node with a mesh (without one it is ignored, with a warning, by the
    // conversion): accessors of the types the extension allows (custom "_" attributes and others: any), one count.
    void instancing() const {
        for (size_t i = 0; i < m.nodes.size(); ++i) {
            const tinygltf::Value* x = gltf::instancing(m.nodes[i]);
            if (!x || m.nodes[i].mesh < 0) continue;
            const std::string path = at("nodes", i) + ".extensions." + kInstancing;
            if (!x->IsObject()) fail(file, path, "must be an object");
            const tinygltf::Value* attrs = x->Has("attributes") ? &x->Get("attributes") : nullptr;
            if (!attrs || !attrs->IsObject() || attrs->Keys().empty())
                fail(file, path + ".attributes", "must be an object naming at least one accessor");
            std::string first;
            size_t count = 0;
            for (const std::string& name : attrs->Keys()) {
                const std::string ap = path + ".attributes." + name;
                const tinygltf::Value& v = attrs->Get(name);
                if (!v.IsNumber() || v.GetNumberAsDouble() != std::floor(v.GetNumberAsDouble()) ||
                    std::abs(v.GetNumberAsDouble()) > 2147483647.0)
                    fail(file, ap, "must be an accessor index");
                const int acc = v.GetNumberAsInt();
                if (name == "TRANSLATION" || name == "SCALE") {
                    attribute(ap, acc, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT});
                } else if (name == "ROTATION") {
                    attribute(
                        ap, acc, TINYGLTF_TYPE_VEC4,
                        {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT});
                    const tinygltf::Accessor& a = m.accessors[size_t(acc)];
                    if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized)
                        fail(file, ap,
                             "accessor " + std::to_string(acc) + " of componentType " +
                                 std::to_string(a.componentType) + " must be normalized");
                } else {
                    index(ap, acc, m.accessors.size(), "accessor");  // not read
                }
                const size_t n = m.accessors[size_t(acc)].count;
                if (first.empty()) {
                    first = name;
                    count = n;
                } else if (n != count) {
                    fail(file, ap,
                         "count " + std::to_string(n) + " differs from " + first + "'s count " + std::to_string(count));
                }
            }
            if (count > kMaxInstances)
                fail(file, path + ".attributes",
                     std::to_string(count) + " instances are more than " + std::to_string(kMaxInstances));
        }
    }

    // Every node at most one parent, no cycle, no chain deeper than kMaxNodeDepth; scenes list roots only.
    void nodes() const {
        const size_t n = m.nodes.size();
        std::vector<int> parent(n, -1);
        for (size_t i = 0; i < n; ++i) {
            const tinygltf::Node& nd = m.nodes[i];
            const std::string path = at("nodes", i);
            index(path + ".mesh", nd.mesh, m.meshes.size(), "mesh", true);
            index(path + ".camera", nd.camera, m.cameras.size(), "camera", true);
            finite(path + ".matrix", nd.matrix, 16);
            finite(path + ".translation", nd.translation, 3);
            finite(path + ".rotation", nd.rotation, 4);
            finite(path + ".scale", nd.scale, 3);
            for (size_t k = 0; k < nd.children.size(); ++k) {
                const int c = nd.children[k];
                const std::string cp = at(path + ".children", k);
                index(cp, c, n, "node");
                if (c == int(i)) fail(file, cp, "node " + std::to_string(c) + " is its own child (a cycle)");
                if (parent[size_t(c)] != -1)
                    fail(file, cp,
                         "node " + std::to_string(c) + " has two parents: nodes[" + std::to_string(parent[size_t(c)]) +
                             "] and nodes[" + std::to_string(i) + "]");
                parent[size_t(c)] = int(i);
            }
        }
        // With one parent each, a cycle is a parent chain that comes back: walk up from every node, marking
        // the walk; 2 = known to reach a root, 1 = on the current walk.
        std::vector<uint8_t> state(n, 0);
        std::vector<int> walk;
        for (size_t s = 0; s < n; ++s) {
            walk.clear();
            int v = int(s);
            while (v != -1 && state[size_t(v)] == 0) {
                state[size_t(v)] = 1;
                walk.push_back(v);
                v = parent[size_t(v)];
            }
            if (v != -1 && state[size_t(v)] == 1) {  // came back to this walk: a cycle through v
                std::string cycle = "nodes[" + std::to_string(v) + "]";
                int u = v;
                do {
                    const int p = parent[size_t(u)];
                    cycle = "nodes[" + std::to_string(p) + "] -> " + cycle;
                    u = p;
                } while (u != v);
                const int p = parent[size_t(v)];
                const auto& ch = m.nodes[size_t(p)].children;
                const size_t k = size_t(std::find(ch.begin(), ch.end(), v) - ch.begin());
                fail(file, at(at("nodes", size_t(p)) + ".children", k), "the node hierarchy has a cycle: " + cycle);
            }
            for (int w : walk) state[size_t(w)] = 2;
        }
        // Depth: walk down from the roots with an explicit stack.
        std::vector<std::pair<int, int>> stack;
        for (size_t i = 0; i < n; ++i)
            if (parent[i] == -1) stack.push_back({int(i), 1});
        while (!stack.empty()) {
            const auto [v, d] = stack.back();
            stack.pop_back();
            if (d > kMaxNodeDepth)
                fail(file, at("nodes", size_t(v)),
                     "the node hierarchy is deeper than " + std::to_string(kMaxNodeDepth) + " levels");
            for (int c : m.nodes[size_t(v)].children) stack.push_back({c, d + 1});
        }
        for (size_t s = 0; s < m.scenes.size(); ++s) {
            std::set<int> seen;
            for (size_t k = 0; k < m.scenes[s].nodes.size(); ++k) {
                const int r = m.scenes[s].nodes[k];
                const std::string path = at(at("scenes", s) + ".nodes", k);
                index(path, r, n, "node");
                if (parent[size_t(r)] != -1)
                    fail(file, path,
                         "node " + std::to_string(r) + " is not a root node (its parent is nodes[" +
                             std::to_string(parent[size_t(r)]) + "])");
                if (!seen.insert(r).second) fail(file, path, "node " + std::to_string(r) + " is listed twice");
            }
        }
        if (m.defaultScene != -1) index("scene", m.defaultScene, m.scenes.size(), "scene");
    }
};

}  // namespace

void prevalidate(const std::string& file, const unsigned char* p, size_t size, bool binary) {
    if (size > 0xffffffffu) fail(file, "", "file is 4 GB or larger (" + std::to_string(size) + " bytes)");
    if (!binary) {
        checkJsonDepth(file, p, size);
        return;
    }
    if (size < 20) fail(file, "", "GLB is " + std::to_string(size) + " bytes, shorter than its 20-byte header");
    const uint32_t version = le32(p + 4), length = le32(p + 8), jsonLen = le32(p + 12), jsonType = le32(p + 16);
    if (version != 2) fail(file, "", "GLB version " + std::to_string(version) + " is not 2");
    if (length > size)
        fail(file, "", "GLB header claims " + std::to_string(length) + " bytes, the file has " + std::to_string(size));
    if (jsonType != 0x4E4F534Au) fail(file, "", "GLB's first chunk is not JSON");
    if (uint64_t(jsonLen) + 20 > length)
        fail(file, "",
             "GLB JSON chunk of " + std::to_string(jsonLen) + " bytes runs past the file's length " +
                 std::to_string(length));
    const uint64_t binAt = 20ull + jsonLen;
    if (binAt < length) {
        if (binAt + 8 > length) fail(file, "", "GLB BIN chunk header is cut off");
        const uint32_t binLen = le32(p + binAt);
        if (binAt + 8 + binLen > length)
            fail(file, "",
                 "GLB BIN chunk of " + std::to_string(binLen) + " bytes runs past the file's length " +
                     std::to_string(length));
    }
    checkJsonDepth(file, p + 20, jsonLen);
}

void validate(const std::string& file, const tinygltf::Model& model) {
    // tinygltf reads any JSON object as an empty model; glTF requires asset.version ("2.0", or a later 2.x).
    if (model.asset.version.empty()) fail(file, "asset.version", "missing: not a glTF 2.0 file");
    if (model.asset.version.rfind("2.", 0) != 0)
        fail(file, "asset.version", "glTF " + model.asset.version + " is not supported (2.0 is)");
    const Checker c{file, model};
    c.extensions();
    c.bufferViews();
    c.accessors();
    c.meshes();
    c.materials();
    c.cameras();
    checkSkins(file, model);  // before the node checks: a joint's two parents or cycle is named as the skin's
    c.nodes();
    c.instancing();
}

}  // namespace sg::gltf
