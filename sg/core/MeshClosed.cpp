#include "sg/core/internal/MeshClosed.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>

namespace sg {

namespace {

// Equal positions, bit for bit once -0 is 0: the corners a mesh duplicates for its normals or UVs at a seam.
struct PositionKey {
    uint32_t x, y, z;
    bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PositionHash {
    size_t operator()(const PositionKey& k) const {
        uint64_t h = (uint64_t(k.x) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full) ^
                     (uint64_t(k.z) * 0x165667B19E3779F9ull);
        return size_t(h ^ (h >> 29));
    }
};
uint32_t bits(float f) {
    if (f == 0.0f) f = 0.0f;
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

// LSD radix sort of keys below 2^bits, 11 bits a pass (std::sort falls back to heap sort on the edges' patterns).
void radixSort(std::vector<uint64_t>& keys, int bits) {
    std::vector<uint64_t> tmp(keys.size());
    std::vector<size_t> count(2048);
    for (int shift = 0; shift < bits; shift += 11) {
        std::fill(count.begin(), count.end(), 0);
        for (const uint64_t k : keys) ++count[(k >> shift) & 2047u];
        size_t sum = 0;
        for (size_t& c : count) sum += std::exchange(c, sum);
        for (const uint64_t k : keys) tmp[count[(k >> shift) & 2047u]++] = k;
        keys.swap(tmp);
    }
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

}  // namespace

bool boundsSolids(const std::vector<vec3>& positions, const uint16_t* indices16, const uint32_t* indices32,
                  size_t indexCount) {
    if (indexCount == 0 || indexCount % 3 != 0) return false;
    // Welded ids: one per distinct position (an open-addressed table of the first vertex at each position).
    std::vector<uint32_t> weld(positions.size());
    size_t capacity = 16;
    while (capacity < positions.size() * 2) capacity *= 2;
    std::vector<uint32_t> table(capacity, ~0u);
    uint32_t distinct = 0;
    for (size_t i = 0; i < positions.size(); ++i) {
        const vec3& p = positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
        const PositionKey k{bits(p.x), bits(p.y), bits(p.z)};
        size_t slot = PositionHash()(k) & (capacity - 1);
        while (table[slot] != ~0u) {
            const vec3& q = positions[table[slot]];
            if (PositionKey{bits(q.x), bits(q.y), bits(q.z)} == k) break;
            slot = (slot + 1) & (capacity - 1);
        }
        if (table[slot] == ~0u) {
            table[slot] = uint32_t(i);
            weld[i] = distinct++;
        } else {
            weld[i] = weld[table[slot]];
        }
    }
    const auto corner = [&](size_t k) { return weld[indices16 ? indices16[k] : indices32[k]]; };

    // Each edge once per triangle along it: the welded ends, lower first, and whether the triangle runs along it
    // downward. Sorted, a closed mesh's edges come in pairs, one each way, and no edge comes more than twice.
    if (distinct >= (1u << 31)) return false;
    std::vector<uint64_t> edges;
    edges.reserve(indexCount);
    for (size_t t = 0; t < indexCount; t += 3) {
        const uint32_t v[3] = {corner(t), corner(t + 1), corner(t + 2)};
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) return false;
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = v[e], b = v[(e + 1) % 3];
            edges.push_back(uint64_t(std::min(a, b)) << 33 | uint64_t(std::max(a, b)) << 1 | uint64_t(a > b));
        }
    }
    if (edges.size() % 2) return false;  // an odd number of triangles cannot pair its edges
    int idBits = 1;
    while ((uint64_t(1) << idBits) < distinct) ++idBits;
    radixSort(edges, 33 + idBits);
    for (size_t i = 0; i < edges.size(); i += 2) {
        if ((edges[i] & 1u) || edges[i + 1] != (edges[i] | 1u)) return false;
        if (i + 2 < edges.size() && (edges[i + 2] >> 1) == (edges[i] >> 1)) return false;
    }

    // Each connected part's signed volume (the divergence theorem over its triangles) must be positive.
    std::vector<uint32_t> parent(distinct);
    std::iota(parent.begin(), parent.end(), 0u);
    for (size_t t = 0; t < indexCount; t += 3) {
        const uint32_t a = findRoot(parent, corner(t));
        parent[findRoot(parent, corner(t + 1))] = a;
        parent[findRoot(parent, corner(t + 2))] = a;
    }
    std::vector<double> volume(distinct, 0.0);
    for (size_t t = 0; t < indexCount; t += 3) {
        const dvec3 a(positions[indices16 ? indices16[t] : indices32[t]]);
        const dvec3 b(positions[indices16 ? indices16[t + 1] : indices32[t + 1]]);
        const dvec3 c(positions[indices16 ? indices16[t + 2] : indices32[t + 2]]);
        volume[findRoot(parent, corner(t))] += glm::dot(a, glm::cross(b, c));
    }
    for (uint32_t v = 0; v < parent.size(); ++v)
        if (parent[v] == v && !(volume[v] > 0.0)) return false;
    return true;
}

}  // namespace sg
