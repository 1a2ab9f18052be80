// BvhCache: a query's hierarchies by mesh (MeshBvh over triangles, PointBvh over points and segments), built on
// first use and rebuilt when the mesh was set again since (Mesh::version). Holds a reference to each mesh it has
// seen, so that a mesh's address is not reused while its hierarchy is kept.
#pragma once
#include "sg/core/Mesh.h"
#include "sg/core/Ref.h"

#include <cstddef>
#include <memory>
#include <unordered_map>

namespace sg {

template <class Bvh>
class BvhCache {
public:
    const Bvh& get(const Mesh& mesh) {
        Entry& e = map_[&mesh];
        if (!e.bvh || e.version != mesh.version()) {
            e.mesh = &mesh;
            e.version = mesh.version();
            e.bvh = std::make_unique<Bvh>(mesh);
        }
        return *e.bvh;
    }
    size_t size() const { return map_.size(); }
    void clear() { map_.clear(); }

private:
    struct Entry {
        ref_ptr<const Mesh> mesh;
        uint64_t version = 0;
        std::unique_ptr<Bvh> bvh;
    };
    std::unordered_map<const Mesh*, Entry> map_;
};

}  // namespace sg
