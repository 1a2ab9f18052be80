// ObbTree: a binary tree of tight oriented bounding boxes over one Mesh's triangles, in the mesh's frame: each
// node's box is the smaller of the box along the mesh's axes and the box along the principal axes of its
// vertices; a node is split in two along its box's longest axis until 10 triangles are left. The occlusion
// map tests a geometry's boxes top down, for screen rectangles tighter than its world axis-aligned box.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"
#include "sg/core/MeshCache.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace sg {

class ObbTree {
public:
    static constexpr uint32_t kLeafTriangles = 10;

    // Triangles with a non-finite vertex make the tree empty (such a mesh is never culled by it).
    explicit ObbTree(const Mesh& mesh);

    struct Node {
        dvec3 centre;
        dvec3 axis[3];       // unit, orthogonal
        dvec3 half;          // half extents along the axes, rounded outward
        uint32_t first = 0;  // inner: children at first and first + 1; 0: a leaf
        uint32_t triangles = 0;
        // Corners in the order of box corners (bit 0: +axis 0, bit 1: +axis 1, bit 2: +axis 2).
        void corners(dvec3 out[8]) const;
    };
    bool empty() const { return nodes_.empty(); }
    const Node& root() const { return nodes_[0]; }
    const Node& node(uint32_t i) const { return nodes_[i]; }
    size_t nodeCount() const { return nodes_.size(); }
    int depth() const { return depth_; }

    // Trees by mesh, built on first use, rebuilt when the mesh was set again (Mesh::version). Entries not
    // asked for in `keepFrames` calls of nextFrame() are dropped, with their reference to the mesh.
    class Cache {
    public:
        const ObbTree& get(const Mesh& mesh);
        void nextFrame(uint64_t keepFrames = 256) { cache_.nextFrame(keepFrames); }
        size_t size() const { return cache_.size(); }

    private:
        MeshCache<ObbTree> cache_;
    };

private:
    void build(std::vector<uint32_t>& tris, size_t begin, size_t end, uint32_t self, int level);
    Node fit(const std::vector<uint32_t>& tris, size_t begin, size_t end) const;

    std::vector<dvec3> pos_;
    std::vector<uint32_t> idx_;
    std::vector<dvec3> centroid_;
    std::vector<Node> nodes_;
    int depth_ = 0;
};

}  // namespace sg
