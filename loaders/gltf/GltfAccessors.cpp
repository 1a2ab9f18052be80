// glTF accessors read into the vectors a Mesh holds: attributes as float vectors (unit ones renormalized) and
// indices, checked against the vertices.
#include "loaders/gltf/internal/GltfConverter.h"

#include <cstring>

namespace sg::gltf {

template <class V, int N>
std::vector<V> readVectors(const tinygltf::Model& m, int acc) {
    const tinygltf::Accessor& a = m.accessors[size_t(acc)];
    const AccessorReader r(m, a);
    const int have = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    std::vector<V> out(a.count);
    if (r.base && r.comp == TINYGLTF_COMPONENT_TYPE_FLOAT && have == N && r.stride == sizeof(V)) {
        std::memcpy(out.data(), r.base, a.count * sizeof(V));
        return out;
    }
    for (size_t i = 0; i < a.count; ++i) {
        V v(1.0f);
        for (int k = 0; k < std::min(N, have); ++k) v[k] = r.component(i, k);
        out[i] = v;
    }
    return out;
}

template <class V>
std::vector<V> readUnitVectors(const tinygltf::Model& m, int acc) {
    std::vector<V> out = readVectors<V, V::length()>(m, acc);
    if (m.accessors[size_t(acc)].componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) return out;
    for (V& v : out) {
        const vec3 d(v);
        const float len = glm::length(d);
        if (len > 0.0f) {
            const vec3 u = d / len;
            for (int k = 0; k < 3; ++k) v[k] = u[k];
        }
    }
    return out;
}

// The kinds the meshes read: positions, UV sets and colours; normals and tangents.
template std::vector<vec2> readVectors<vec2, 2>(const tinygltf::Model&, int);
template std::vector<vec3> readVectors<vec3, 3>(const tinygltf::Model&, int);
template std::vector<vec4> readVectors<vec4, 4>(const tinygltf::Model&, int);
template std::vector<vec3> readUnitVectors<vec3>(const tinygltf::Model&, int);
template std::vector<vec4> readUnitVectors<vec4>(const tinygltf::Model&, int);

std::vector<uint32_t> Converter::indices(const tinygltf::Primitive& p, size_t n, const std::string& path) {
    std::vector<uint32_t> idx;
    if (p.indices >= 0) {
        const tinygltf::Accessor& a = m.accessors[size_t(p.indices)];
        const AccessorReader r(m, a);
        idx.resize(a.count);
        uint32_t mx = 0;
        if (r.base && r.comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && r.stride == 2) {
            const unsigned char* b = r.base;
            for (size_t i = 0; i < a.count; ++i) {
                uint16_t v;
                std::memcpy(&v, b + 2 * i, 2);
                idx[i] = v;
                mx = std::max<uint32_t>(mx, v);
            }
        } else {
            for (size_t i = 0; i < a.count; ++i) mx = std::max(mx, idx[i] = r.index(i));
        }
        if (mx >= n) {
            size_t i = 0;
            while (idx[i] < n) ++i;
            bad(path + ".indices", "index " + std::to_string(idx[i]) + " at element " + std::to_string(i) +
                                       " is out of range (" + std::to_string(n) + " vertices)");
        }
    } else {
        idx.resize(n);
        for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
    }
    return idx;
}

}  // namespace sg::gltf
