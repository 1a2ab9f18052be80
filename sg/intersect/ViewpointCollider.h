// ViewpointCollider: moves the viewpoint, a sphere, by a step per frame through a scene: collidable geometry
// stops it and it slides along the surface; every move is a swept test (no tunnelling at any speed); an
// optional ground-following mode keeps the eye at a height above the surface below it.
#pragma once
#include "sg/intersect/IntersectTraversal.h"

namespace sg {

struct ViewpointSettings {
    double radius = 0.3;
    // Contacts are found for radius + skin and the sphere stops there: the rounding of the contact time
    // can never leave it closer than `radius`.
    double skin = 1e-4;
    int slides = 5;  // sweeps per step: the first, then slides along what it met
    uint32_t traversalMask = kCollidable;
    bool groundFollow = false;
    double eyeHeight = 1.7;  // ground following: the eye this high above the surface below it
    double maxClimb = 0.5;   // ground following: a higher step up is a wall, not a stair
    double maxFall = 0.5;    // ground following: the most it sinks per step when nothing is below within reach
    dvec3 up{0.0, 0.0, 1.0};
};

struct ViewpointStats {
    int sweeps = 0;
    int contacts = 0;
    bool grounded = false;  // ground following: a surface was found below
};

class ViewpointCollider {
public:
    // Throws std::invalid_argument naming the setting for a negative or non-finite radius, skin, height,
    // climb or fall, fewer than one slide, or a zero or non-finite up vector.
    explicit ViewpointCollider(const ViewpointSettings& settings = {});
    const ViewpointSettings& settings() const { return set_; }

    // The position reached from `from` by `step`. Throws std::invalid_argument for a non-finite point or
    // step (and as IntersectTraversal does for a stale scene).
    dvec3 move(const Scene& scene, const dvec3& from, const dvec3& step);
    const ViewpointStats& lastStats() const { return stats_; }
    IntersectTraversal& traversal() { return isect_; }

private:
    dvec3 slide(const Scene& scene, dvec3 p, dvec3 motion);
    ViewpointSettings set_;
    dvec3 up_{0.0, 0.0, 1.0};
    QueryOptions opt_;
    IntersectTraversal isect_;
    ViewpointStats stats_;
};

}  // namespace sg
