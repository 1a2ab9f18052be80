// PointBvh: a bounding-volume hierarchy over one Mesh's points or line segments (Mesh::primitive() Points or
// Lines), in the mesh's own frame, for picking them within a cone about a ray; built once and shared by every
// placement of the mesh.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"
#include "sg/intersect/BvhCache.h"

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace sg {

class PointBvh {
public:
    // Points or segments with a non-finite end are left out (they cannot be hit). A triangle mesh gives an empty
    // hierarchy: its outline is not picked apart from its faces.
    explicit PointBvh(const Mesh& mesh);

    // A ray origin + t * direction, t in [0, tMax], in the query's frame, with the cone about it: at distance
    // s = t * |direction| from the origin its radius is width + s * slope. `a` and `offset` map the mesh's frame
    // to the query's (p -> a * p + offset): the cone keeps its size in the query's units whatever the scale.
    struct Cone {
        dvec3 origin{0.0}, direction{0.0, 0.0, -1.0};
        double tMax = kInf;
        double width = 0.0, slope = 0.0;
        glm::dmat3 a{1.0};
        dvec3 offset{0.0};
    };
    // The cone seen from the frame `a` and `offset` map from (a mesh's, an image's): how a box of that frame is
    // widened to hold every point of it the cone reaches, so that boxes are pruned in their own frame.
    struct ConeFrame {
        dvec3 o{0.0}, inv{0.0};  // the ray's origin and 1 / direction in the frame
        dvec3 along{0.0};        // a^T of the query's unit direction: distance along the ray = dot(p - o, along)
        dvec3 reach{0.0};        // per axis: the norm of that row of a^-1 (a query length r spans r * reach there)
        double width = 0.0, slope = 0.0;
        bool valid = false;  // false when a is singular or the cone is not finite

        static ConeFrame make(const Cone& cone);
        // The cone's radius at distance s along the ray (query's units), widened a little: a point on the cone's
        // edge, accepted by the exact test in the query's frame, is not pruned by the rounding of a box.
        double radiusAt(double s) const { return (width + (s > 0.0 ? s : 0.0) * slope) * (1.0 + 1e-9); }
        // Whether the cone reaches into the box [mn, mx] before tMax; tNear: where the ray enters the box widened by
        // the cone's radius at the box's far end along the ray (the widest the cone is over the box).
        bool enter(const double* mn, const double* mx, double tMax, double& tNear) const noexcept;
        // A sphere's radius widened likewise (for a test of the ray's distance to its centre).
        double sphereReach(const dvec3& centre, double r) const;
    };
    struct ConeHit {
        double t = kInf;         // the ray parameter of the point (or of the ray's point nearest the segment)
        uint32_t primitive = 0;  // point or segment index in the mesh
        double u = 0.0;          // on a segment: point = (1 - u) p0 + u p1; 0 for a point
        dvec3 point{0.0};        // the point, or the segment's point nearest the ray (query's frame)
    };

    // The hit with the smallest t; false when nothing lies within the cone.
    bool nearest(const Cone& cone, ConeHit& out) const;
    // Every hit, appended unsorted.
    void all(const Cone& cone, std::vector<ConeHit>& out) const;

    // The exact tests alone, on a point or segment already in the query's frame, with t up to tMax (for the
    // hierarchy, and the brute-force twin of tests and the benchmark).
    static bool hitPoint(const Cone& cone, double tMax, const dvec3& p, ConeHit& out) noexcept;
    static bool hitSegment(const Cone& cone, double tMax, const dvec3& p0, const dvec3& p1, ConeHit& out) noexcept;

    const Mesh& mesh() const { return *mesh_; }
    size_t nodeCount() const { return nodes_.size(); }
    size_t bytes() const;

    // Hierarchies by mesh, built on first use (sg/intersect/BvhCache.h).
    using Cache = BvhCache<PointBvh>;

private:
    // 32 bytes. Inner: children at `index` and index + 1; leaf (count > 0): primitives [index, index + count).
    struct Node {
        float min[3];
        uint32_t index;
        float max[3];
        uint32_t count;
    };
    void build(std::vector<dvec3>& centres);
    bool leafHit(const Cone& c, uint32_t k, double tMax, ConeHit& out) const noexcept;

    ref_ptr<const Mesh> mesh_;
    uint32_t ends_ = 1;  // 1 for points, 2 for segments
    std::vector<Node> nodes_;
    std::vector<uint32_t> prims_;  // primitive indices in leaf order
    std::vector<vec3> verts_;      // ends_ per entry of prims_, in leaf order
};

}  // namespace sg
