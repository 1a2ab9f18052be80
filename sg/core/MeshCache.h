// Data derived from a mesh (an ObbTree, TriangleClusters), kept per mesh: built on first use, built again when
// the mesh was set again (Mesh::version) or asked for with another key (a parameter of the build), and dropped,
// with its reference to the mesh, when not asked for in `keepFrames` calls of nextFrame().
#pragma once
#include "sg/core/Mesh.h"
#include "sg/core/Ref.h"

#include <cstdint>
#include <iterator>
#include <memory>
#include <unordered_map>

namespace sg {

template <class T>
class MeshCache {
public:
    // `make()` returns a std::unique_ptr<T> built from `mesh` with `key`.
    template <class Make>
    const T& get(const Mesh& mesh, uint64_t key, Make make) {
        Entry& e = map_[&mesh];
        if (!e.value || e.version != mesh.version() || e.key != key) {
            e.mesh = &mesh;
            e.version = mesh.version();
            e.key = key;
            e.value = make();
        }
        e.lastUsed = frame_;
        return *e.value;
    }
    void nextFrame(uint64_t keepFrames = 256) {
        ++frame_;
        if (frame_ % keepFrames) return;
        for (auto it = map_.begin(); it != map_.end();)
            it = frame_ - it->second.lastUsed > keepFrames ? map_.erase(it) : std::next(it);
    }
    size_t size() const { return map_.size(); }

private:
    struct Entry {
        ref_ptr<const Mesh> mesh;
        uint64_t version = 0, key = 0, lastUsed = 0;
        std::unique_ptr<T> value;
    };
    std::unordered_map<const Mesh*, Entry> map_;
    uint64_t frame_ = 0;
};

}  // namespace sg
