#include "loaders/tiles/internal/SharedMeshes.h"

#include "nodes/Geometry.h"
#include "sg/scene/internal/DistinctGeometries.h"

#include <cstring>
#include <unordered_map>
#include <vector>

namespace sg::tiles {
namespace {

// 64-bit words mixed as in splitmix64: fast enough that hashing a tile's meshes costs far less than parsing them.
uint64_t mix(uint64_t h, uint64_t w) {
    h ^= w + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ull;
    return h ^ (h >> 27);
}

template <class T>
uint64_t hashArray(uint64_t h, const std::vector<T>& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    const size_t n = v.size() * sizeof(T);
    h = mix(h, n);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        std::memcpy(&w, p + i, 8);
        h = mix(h, w);
    }
    uint64_t tail = 0;
    if (i < n) std::memcpy(&tail, p + i, n - i);
    return mix(h, tail);
}

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

uint64_t meshHash(const Mesh& m) {
    uint64_t h = hashArray(0, m.positions());
    h = hashArray(h, m.normals());
    h = hashArray(h, m.uvs());
    h = hashArray(h, m.colors());
    h = hashArray(h, m.indices16());
    return hashArray(h, m.indices32());
}

bool sameMesh(const Mesh& a, const Mesh& b) {
    // What draws them and how large points are drawn belong to the mesh too (a point tile's spacing is its error).
    return a.primitive() == b.primitive() && a.pointSpacing() == b.pointSpacing() &&
           sameBytes(a.positions(), b.positions()) && sameBytes(a.normals(), b.normals()) &&
           sameBytes(a.uvs(), b.uvs()) && sameBytes(a.colors(), b.colors()) &&
           sameBytes(a.indices16(), b.indices16()) && sameBytes(a.indices32(), b.indices32());
}

size_t SharedMeshes::share(Node& root) {
    // Hashed outside the lock: the loader threads only wait on each other for the look-ups.
    std::vector<std::pair<Geometry*, uint64_t>> found;
    forEachDistinctGeometry(root, [&](const Geometry& g) {
        // A point tile holds its points once (refinement adds, it never repeats them): no two tiles' clouds are
        // equal, so they are neither hashed nor pooled.
        if (g.mesh() && g.mesh()->primitive() != Primitive::Points)
            found.emplace_back(const_cast<Geometry*>(&g), meshHash(*g.mesh()));
    });
    size_t n = 0;
    std::unordered_map<Mesh*, ref_ptr<Mesh>> decided;  // a mesh several Geometries hold is looked up once
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& [g, h] : found) {
        Mesh* mine = g->mesh();
        auto d = decided.find(mine);
        if (d == decided.end()) {
            ref_ptr<Mesh> equal;
            for (auto [it, end] = pool_.equal_range(h); it != end && !equal; ++it)
                if (it->second.get() == mine || sameMesh(*it->second, *mine)) equal = it->second;
            if (!equal) {
                equal = mine;
                pool_.emplace(h, equal);
                ++insertsSinceDrop_;
            } else if (equal.get() != mine) {
                ++n;
            }
            d = decided.emplace(mine, equal).first;
        }
        if (d->second.get() != mine) g->setMesh(d->second);
    }
    replaced_ += n;
    // Amortised: a sweep costs the pool's size, run once the pool has grown by half of it.
    if (insertsSinceDrop_ > pool_.size() / 2) dropUnused();
    return n;
}

void SharedMeshes::dropUnused() {
    // Held only here (a count of one) means no graph holds it, and no other thread can get it but through the
    // pool, under this lock: dropping it is safe.
    for (auto it = pool_.begin(); it != pool_.end();)
        it = it->second->refCount() == 1 ? pool_.erase(it) : std::next(it);
    insertsSinceDrop_ = 0;
}

size_t SharedMeshes::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pool_.size();
}

size_t SharedMeshes::replaced() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return replaced_;
}

}  // namespace sg::tiles
