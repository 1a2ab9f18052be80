// Equal meshes loaded by different tiles made one: a tileset's tiles each carry their own copy of the meshes they
// share (a city's building kinds are in every tile's file), and without this each copy would be held, welded for
// closed() and uploaded again. Keyed by a hash of the arrays and confirmed by comparing them, so only meshes equal
// to the bit are merged. Any thread may call it (the pager's loader threads do).
// Internal header: not installed.
#pragma once
#include "sg/core/Mesh.h"
#include "sg/core/Node.h"

#include <cstddef>
#include <mutex>
#include <unordered_map>

namespace sg::tiles {

class SharedMeshes {
public:
    // Points every Geometry below `root` (a graph no other thread sees yet) at the pool's equal mesh, adding the
    // ones the pool does not have. Returns how many meshes it replaced.
    size_t share(Node& root);
    // Meshes held by the pool; entries nothing else holds are dropped as loads go on.
    size_t size() const;
    size_t replaced() const;

private:
    void dropUnused();  // with mutex_ held

    mutable std::mutex mutex_;
    std::unordered_multimap<uint64_t, ref_ptr<Mesh>> pool_;
    size_t replaced_ = 0;
    size_t insertsSinceDrop_ = 0;
};

// A hash of a mesh's arrays (positions, normals, UVs, colours, indices), equal for equal meshes.
uint64_t meshHash(const Mesh& m);
// Whether two meshes' arrays are equal element for element, bit for bit.
bool sameMesh(const Mesh& a, const Mesh& b);

}  // namespace sg::tiles
