// TriangleClusters: a Mesh's triangles in runs of K consecutive ones (index order), each with its local box, for
// the cull's screen-rectangle rejection (CullSettings::screenRect): a cluster whose box lies outside the viewport
// is left out of the item's draw.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"
#include "sg/core/MeshCache.h"
#include "sg/cull/DrawList.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace sg {

class TriangleClusters {
public:
    // Throws std::invalid_argument unless 1 <= trianglesPerCluster <= 65536. A mesh with a non-finite position
    // gets no clusters (empty(): never rejected).
    TriangleClusters(const Mesh& mesh, uint32_t trianglesPerCluster);

    // Centre and half extent in the mesh's frame, rounded outward from the float positions: every vertex of
    // the cluster's triangles lies within [centre - half, centre + half] exactly.
    struct Bounds {
        vec3 centre, half;
    };
    bool empty() const { return bounds_.empty(); }
    size_t size() const { return bounds_.size(); }
    uint32_t trianglesPerCluster() const { return per_; }
    const Bounds& operator[](size_t i) const { return bounds_[i]; }
    const std::vector<Bounds>& bounds() const { return bounds_; }
    // Cluster i is triangles [i * K, min((i + 1) * K, triangles)).
    uint32_t triangleCount() const { return triangles_; }

    // The screen-rectangle rejection: appends to `out` the index ranges of the clusters not wholly beyond one
    // side of the viewport (adjacent ones merged) and returns their triangle count. viewProj: eye-relative world
    // -> clip (Camera::projection() * viewRotation()); model: local -> eye-relative world (DrawItem::model). A
    // cluster is left out when, for one of x >= -w, x <= w, y >= -w, y <= w, every point of its box fails by more
    // than the float rounding the GPU's transform can make; then no vertex of it reaches the viewport. Boxes
    // behind the eye or across the near plane need no case of their own (w < 0 fails x >= -w only where x < -w).
    // `tested` and `rejected` count clusters. Empty clusters: every triangle kept, one range.
    uint32_t keepInViewport(const dmat4& viewProj, const dmat4& model, std::vector<IndexRange>& out, uint64_t& tested,
                            uint64_t& rejected) const;
    // Its naive twin: each triangle's three vertices projected to the screen, as the paper does, kept when its
    // rectangle (xmin..xmax, ymin..ymax over the vertices with w > 0; any vertex at w <= 0 keeps it) meets the
    // viewport. For tests and the benchmark: what per-triangle rejection would leave, in triangles.
    static uint32_t keepTrianglesNaive(const Mesh& mesh, const dmat4& viewProj, const dmat4& model);

    // Clusters by mesh, built on first use, rebuilt when the mesh was set again (Mesh::version) or the cluster
    // size changed. Entries not asked for in `keepFrames` calls of nextFrame() are dropped.
    class Cache {
    public:
        const TriangleClusters& get(const Mesh& mesh, uint32_t trianglesPerCluster);
        void nextFrame(uint64_t keepFrames = 256) { cache_.nextFrame(keepFrames); }
        size_t size() const { return cache_.size(); }

    private:
        MeshCache<TriangleClusters> cache_;
    };

private:
    std::vector<Bounds> bounds_;
    uint32_t per_ = 1, triangles_ = 0;
    dvec3 reach_{0.0};  // the largest |coordinate| of any vertex, per axis (the rounding bound's scale)
};

}  // namespace sg
