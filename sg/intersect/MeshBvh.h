// MeshBvh: a bounding-volume hierarchy over one Mesh's triangles, in the mesh's own frame, built once and
// shared by every placement of the mesh; watertight ray tests (Woop, Benthin, Wald 2013) in double.
#pragma once
#include "sg/core/Assert.h"
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"
#include "sg/intersect/BvhCache.h"

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace sg {

class MeshBvh {
public:
    // Triangles with a non-finite vertex are left out (they cannot be hit).
    explicit MeshBvh(const Mesh& mesh);

    struct RayHit {
        double t = kInf;
        uint32_t primitive = 0;
        double u = 0.0, v = 0.0;  // weights of the triangle's second and third vertex
    };
    // Nearest hit with t in [0, tMax] of the ray o + t d (the mesh's frame); false when none. A ray through
    // an edge or vertex shared by triangles hits at least one of them (watertight).
    bool nearest(const dvec3& o, const dvec3& d, double tMax, RayHit& out) const noexcept;
    // Every hit with t in [0, tMax], appended unsorted.
    void all(const dvec3& o, const dvec3& d, double tMax, std::vector<RayHit>& out) const;
    // Calls f(primitive) once for every triangle whose box overlaps b (the mesh's frame), and for the others
    // of the leaves it meets: the caller tests each triangle exactly anyway.
    template <class F>
    void overlapping(const Box& b, F&& f) const;

    // Watertight ray/triangle test alone (two-sided; for the light baker, tests and the naive twin in the benchmark).
    static bool rayTriangle(const dvec3& o, const dvec3& d, double tMax, const dvec3& p0, const dvec3& p1,
                            const dvec3& p2, RayHit& out) noexcept;

    const Mesh& mesh() const { return *mesh_; }
    size_t nodeCount() const { return nodes_.size(); }
    size_t bytes() const;
    // The triangle's vertices (mesh frame).
    void triangle(uint32_t primitive, dvec3& p0, dvec3& p1, dvec3& p2) const;

    // Hierarchies by mesh, built on first use (sg/intersect/BvhCache.h).
    using Cache = BvhCache<MeshBvh>;

private:
    // 32 bytes. Inner: children at `index` and index + 1; leaf (count > 0): triangles [index, index + count).
    struct Node {
        float min[3];
        uint32_t index;
        float max[3];
        uint32_t count;
    };
    uint32_t build(uint32_t first, uint32_t count, std::vector<Box>& boxes, std::vector<dvec3>& centroids);

    ref_ptr<const Mesh> mesh_;
    std::vector<Node> nodes_;
    std::vector<uint32_t> prims_;  // triangle indices in leaf order
    std::vector<vec3> verts_;      // three per entry of prims_, in leaf order
};

template <class F>
void MeshBvh::overlapping(const Box& b, F&& f) const {
    if (nodes_.empty()) return;
    uint32_t stack[128];  // the build bounds the depth (median splits below depth 40)
    int top = 0;
    stack[top++] = 0;
    while (top) {
        const Node& n = nodes_[stack[--top]];
        if (n.min[0] > b.max.x || n.min[1] > b.max.y || n.min[2] > b.max.z || n.max[0] < b.min.x ||
            n.max[1] < b.min.y || n.max[2] < b.min.z)
            continue;
        if (n.count) {
            for (uint32_t k = 0; k < n.count; ++k) f(prims_[n.index + k]);
        } else {
            SG_ASSERT(top + 2 <= 128, "MeshBvh::overlapping(): traversal stack overflow");
            stack[top++] = n.index + 1;
            stack[top++] = n.index;
        }
    }
}

}  // namespace sg
