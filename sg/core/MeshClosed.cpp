#include "sg/core/MeshClosed.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace sg {

namespace {

// Equal positions, bit for bit once -0 is 0: the corners a mesh duplicates for its normals or UVs at a seam.
struct PositionKey {
    uint32_t x, y, z;
    bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PositionHash {
    size_t operator()(const PositionKey& k) const {
        return size_t(k.x) * 73856093u ^ size_t(k.y) * 19349663u ^ size_t(k.z) * 83492791u;
    }
};
uint32_t bits(float f) {
    if (f == 0.0f) f = 0.0f;
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

}  // namespace

bool boundsSolids(const std::vector<vec3>& positions, const uint16_t* indices16, const uint32_t* indices32,
                  size_t indexCount) {
    if (indexCount == 0 || indexCount % 3 != 0) return false;
    // Welded ids: one per distinct position.
    std::vector<uint32_t> weld(positions.size());
    std::unordered_map<PositionKey, uint32_t, PositionHash> ids;
    ids.reserve(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        const vec3& p = positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
        weld[i] = ids.emplace(PositionKey{bits(p.x), bits(p.y), bits(p.z)}, uint32_t(ids.size())).first->second;
    }
    const auto corner = [&](size_t k) { return weld[indices16 ? indices16[k] : indices32[k]]; };

    // Directed edges, sorted: each must be there once, and its reverse too.
    std::vector<uint64_t> edges;
    edges.reserve(indexCount);
    for (size_t t = 0; t < indexCount; t += 3) {
        const uint32_t v[3] = {corner(t), corner(t + 1), corner(t + 2)};
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) return false;
        for (int e = 0; e < 3; ++e) edges.push_back(uint64_t(v[e]) << 32 | v[(e + 1) % 3]);
    }
    std::sort(edges.begin(), edges.end());
    if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
    for (const uint64_t e : edges)
        if (!std::binary_search(edges.begin(), edges.end(), (e << 32) | (e >> 32))) return false;

    // Each connected part's signed volume (the divergence theorem over its triangles) must be positive.
    std::vector<uint32_t> parent(ids.size());
    std::iota(parent.begin(), parent.end(), 0u);
    for (size_t t = 0; t < indexCount; t += 3) {
        const uint32_t a = findRoot(parent, corner(t));
        parent[findRoot(parent, corner(t + 1))] = a;
        parent[findRoot(parent, corner(t + 2))] = a;
    }
    std::unordered_map<uint32_t, double> volume;
    for (size_t t = 0; t < indexCount; t += 3) {
        const dvec3 a(positions[indices16 ? indices16[t] : indices32[t]]);
        const dvec3 b(positions[indices16 ? indices16[t + 1] : indices32[t + 1]]);
        const dvec3 c(positions[indices16 ? indices16[t + 2] : indices32[t + 2]]);
        volume[findRoot(parent, corner(t))] += glm::dot(a, glm::cross(b, c));
    }
    return std::all_of(volume.begin(), volume.end(), [](const auto& v) { return v.second > 0.0; });
}

}  // namespace sg
