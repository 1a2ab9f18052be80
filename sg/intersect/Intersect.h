// Intersection queries and their results: rays and segments, spheres and swept spheres against a scene.
#pragma once
#include "sg/core/Math.h"

#include <cstdint>
#include <vector>

namespace sg {

class Camera;
class FeatureStyle;
class Node;
class Geometry;
class Instance;

// Node mask bits the intersection traversals look for by default (a node is seen when
// nodeMask & traversalMask != 0, as in the cull). High bits, so that masks chosen for drawing keep them.
constexpr uint32_t kPickable = 1u << 30;
constexpr uint32_t kCollidable = 1u << 31;

// Which LOD child a query sees: the one the cull draws for `QueryOptions::camera`, or the most detailed.
enum class LodChoice : uint8_t { AsDrawn, Highest };

struct QueryOptions {
    uint32_t traversalMask = kPickable;
    LodChoice lod = LodChoice::Highest;
    // The view whose LOD levels (AsDrawn) and billboard orientations are seen. Without one, billboards face
    // the query's origin (the ray's or sphere's start) and AsDrawn measures the distance from it.
    const Camera* camera = nullptr;
    double lodScale = 1.0;  // CullSettings::lodScale of that view
    // The features this style hides (sg/style/FeatureStyle.h: the one the view is drawn with) are not hit: a ray
    // passes through them as the picture shows. Per-vertex feature ids of a mesh's first set, as the renderer.
    FeatureStyle* style = nullptr;
    // Points and lines (Mesh::primitive()) are hit by a ray when they pass within a cone about it: at parameter t of
    // a unit direction, within coneWidth + t * coneSlope of the ray (the nearest such point or segment along the
    // ray wins). pickCone() (sg/intersect/PickCone.h) makes it a radius in pixels of a view. Zero: they are not hit.
    double coneWidth = 0.0, coneSlope = 0.0;
};

// A ray origin + t * direction for t in [0, tMax]; a segment from a to b is {a, b - a, 1}.
struct Ray {
    dvec3 origin{0.0};
    dvec3 direction{0.0, 0.0, -1.0};
    double tMax = kInf;
};
inline Ray segment(const dvec3& a, const dvec3& b) { return Ray{a, b - a, 1.0}; }

// One hit, in world coordinates (double).
struct Hit {
    double t = kInf;         // ray parameter of the hit (world distance when the direction is a unit vector)
    double distance = kInf;  // world distance from the query's origin to `point`
    dvec3 point{0.0};
    dvec3 normal{0.0};       // unit geometric normal of the triangle (its winding's front side); zero for points and
                             // lines
    uint32_t primitive = 0;  // triangle, line segment or point index in the mesh (Mesh::primitive())
    // Barycentrics of a triangle: point = (1-u-v) p0 + u p1 + v p2 in the mesh's frame; on a segment, point = (1-u)
    // p0 + u p1 (v = 0); a point's own position for a point (u = v = 0).
    double u = 0.0, v = 0.0;
    // From the root to the Geometry; an Instance appears in it followed by its prototype's subgraph.
    std::vector<Node*> path;
    const Geometry* geometry = nullptr;
    // The innermost Instance on the path (the placement) and its entry index in the image that holds it
    // (stable until the scene's structure changes); null and ~0u outside any Instance.
    const Instance* instance = nullptr;
    uint32_t placement = ~0u;
};

// Result of a swept sphere: the first contact along the motion.
struct SweepHit {
    double t = kInf;    // fraction of the motion travelled at contact, in [0, 1]
    dvec3 point{0.0};   // the contact point on the surface (world)
    dvec3 normal{0.0};  // unit, from the contact point toward the sphere's centre at contact
    std::vector<Node*> path;
    const Geometry* geometry = nullptr;
    uint32_t primitive = 0;
};

}  // namespace sg
