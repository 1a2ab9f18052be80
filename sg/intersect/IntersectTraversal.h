// IntersectTraversal: ray, segment, sphere and swept-sphere queries against a Scene, walking its flat image
// (world bounds prune subtrees) in step with the graph (for the node path), and each geometry's MeshBvh (triangles)
// or PointBvh (points and lines).
#pragma once
#include "sg/core/Pose.h"
#include "sg/intersect/Intersect.h"
#include "sg/intersect/MeshBvh.h"
#include "sg/intersect/PointBvh.h"
#include "sg/scene/Scene.h"

#include <memory>
#include <unordered_map>
#include <vector>

namespace sg {

class Geometry;
class LodChooser;

struct IntersectStats {
    uint64_t entriesVisited = 0;    // image entries reached (after masks)
    uint64_t geometriesTested = 0;  // geometries whose BVH was queried
    uint64_t trianglesTested = 0;   // sphere and sweep queries: triangles given the exact test
};

// Keeps its BVH cache and scratch state between queries: one traversal per thread.
class IntersectTraversal {
public:
    // What the graph shows is seen as the cull sees it: node masks against options.traversalMask, the
    // active children of a Switch, one LOD child (options.lod; AsDrawn mirrors the cull's plain ranges and
    // LOD scale for options.camera, without hysteresis or budget), Billboards turned toward the camera's eye
    // (or the query's origin), every Instance placement. Each throws std::logic_error when the scene
    // changed since its last update(), and std::invalid_argument naming the function and the value for a
    // non-finite or zero-length direction, a negative or NaN tMax or radius, a non-finite point, a negative or
    // non-finite cone.
    // Rays also hit points and line segments (Mesh::primitive()) within the options' cone (QueryOptions::coneWidth,
    // coneSlope; none when both are 0); spheres and swept spheres pass through them: they have no surface to touch
    // or stand on.

    // Nearest hit of the ray; false when none.
    bool intersect(const Scene& scene, const Ray& ray, const QueryOptions& options, Hit& out);
    // Every hit of the ray, nearest first (a ray through a shared edge may report both triangles).
    void intersectAll(const Scene& scene, const Ray& ray, const QueryOptions& options, std::vector<Hit>& out);
    // Every triangle within `radius` of `centre`, nearest first: point is the triangle's nearest point,
    // distance its distance from the centre (t too), normal the triangle's.
    void intersectSphere(const Scene& scene, const dvec3& centre, double radius, const QueryOptions& options,
                         std::vector<Hit>& out);
    // First contact of a sphere moving from `centre` by `motion` (both sides of every triangle); false when
    // it moves freely.
    bool sweepSphere(const Scene& scene, const dvec3& centre, double radius, const dvec3& motion,
                     const QueryOptions& options, SweepHit& out);

    // The per-mesh BVHs, built on first use and shared by every placement of a mesh.
    MeshBvh::Cache& bvhCache() { return cache_; }
    PointBvh::Cache& pointBvhCache() { return pointCache_; }
    const IntersectStats& lastStats() const { return stats_; }

private:
    enum class Mode : uint8_t { Nearest, All, Sphere, Sweep };
    struct Ctx;
    void run(const Scene& scene, const QueryOptions& options, const dvec3& queryOrigin, const char* fn);
    void setupCtx(Ctx& c, const FlatImage& img, const dmat4& imgToRel) const;
    bool test(const Ctx& c, uint32_t i, double& tNear) const;
    bool wideTest(const Ctx& c, uint32_t w) const;
    void visit(Ctx& c, uint32_t i, Node* n, const dmat4& m, bool tested);
    void children(Ctx& c, uint32_t i, Node* n, const dmat4& m);
    void geometry(Node* n, const dmat4& m, const Pose* pose);
    void rayGeometry(Node* n, const MeshBvh& bvh, const glm::dmat3& inv, const dvec3& t);
    void rayPoints(Node* n, const Mesh& mesh, const dmat4& m, const PointBvh* bvh = nullptr);
    // A posed Geometry as it stands in `pose` (IntersectPosed.cpp): its mesh skinned or morphed, with hierarchies
    // built on first use, kept while the Geometry keeps that pose.
    struct Posed {
        ref_ptr<const Node> geometry;
        ref_ptr<const Pose> pose;
        ref_ptr<Mesh> mesh;
        std::unique_ptr<MeshBvh> triangles;
        std::unique_ptr<PointBvh> points;
    };
    Posed& posed(const Geometry& g, const Pose& pose);
    void fillPointHit(Hit& h, Node* n, const PointBvh::ConeHit& r) const;

    // The query, in coordinates relative to `q_` (the camera's eye, or the query's origin): matrices map
    // a node's frame there, so that a scene far from the world origin keeps its precision.
    Mode mode_ = Mode::Nearest;
    const Scene* scene_ = nullptr;
    const QueryOptions* opt_ = nullptr;
    const LodChooser* chooser_ = nullptr;  // the query's LOD rules (sg/lod/internal/LodChooser.h)
    dvec3 q_{0.0};
    dvec3 o_{0.0}, d_{0.0};  // ray, or sphere centre and motion
    double tMax_ = 0.0, radius_ = 0.0;
    bool cone_ = false;  // ray modes: the options' cone is not empty (points and lines are hit)
    Box region_;         // sphere modes: everything the sphere touches (relative)
    // Results
    Hit* best_ = nullptr;
    SweepHit* sweep_ = nullptr;
    std::vector<Hit>* all_ = nullptr;
    bool found_ = false;
    // Walk state
    std::vector<Node*> path_;
    const Instance* instance_ = nullptr;
    uint32_t placement_ = ~0u;
    struct Pending {
        double tNear;
        uint32_t entry, child;
    };
    std::vector<Pending> order_;  // children of a node sorted by distance (a stack of runs)
    std::vector<MeshBvh::RayHit> rayHits_;
    std::vector<PointBvh::ConeHit> coneHits_;
    MeshBvh::Cache cache_;
    PointBvh::Cache pointCache_;
    std::unordered_map<const Geometry*, Posed> posed_;
    IntersectStats stats_;
};

}  // namespace sg
