#include "sg/intersect/ViewpointCollider.h"

#include <stdexcept>
#include <string>

namespace sg {

namespace {
void checkSetting(const char* name, double v, bool positive) {
    if (!(std::isfinite(v) && (positive ? v > 0.0 : v >= 0.0)))
        throw std::invalid_argument(std::string("ViewpointCollider::ViewpointCollider(): ") + name + " " +
                                    std::to_string(v) +
                                    (positive ? " is not a positive number" : " is negative or not finite"));
}
}  // namespace

ViewpointCollider::ViewpointCollider(const ViewpointSettings& s) : set_(s) {
    checkSetting("radius", s.radius, false);
    checkSetting("skin", s.skin, true);
    checkSetting("eyeHeight", s.eyeHeight, false);
    checkSetting("maxClimb", s.maxClimb, false);
    checkSetting("maxFall", s.maxFall, false);
    if (s.slides < 1)
        throw std::invalid_argument("ViewpointCollider::ViewpointCollider(): slides " + std::to_string(s.slides) +
                                    " is less than 1");
    if (!isFinite(s.up) || !(glm::length(s.up) > 0.0))
        throw std::invalid_argument("ViewpointCollider::ViewpointCollider(): up vector is zero or not finite");
    up_ = glm::normalize(s.up);
    opt_.traversalMask = s.traversalMask;
    opt_.lod = LodChoice::Highest;
}

// Sweeps, stops at the first contact and slides the rest of the motion along the surface met, a few times.
// Each move is a sweep of radius + skin that ended before any contact, so the sphere of `radius` never
// ends inside collidable geometry, whatever the speed.
dvec3 ViewpointCollider::slide(const Scene& scene, dvec3 p, dvec3 motion) {
    const double r = set_.radius + set_.skin;
    dvec3 prev(0.0);  // the normal of the last contact
    for (int k = 0; k < set_.slides; ++k) {
        const double len = glm::length(motion);
        if (!(len > eps::kZeroLength)) break;
        SweepHit h;
        stats_.sweeps++;
        if (!isect_.sweepSphere(scene, p, r, motion, opt_, h)) {
            p += motion;
            break;
        }
        stats_.contacts++;
        p += motion * h.t;
        // Away from the surface by half the skin, itself swept: the sphere then slides clear of the surface
        // it touched instead of meeting it again, through rounding, at every later sweep.
        const dvec3 away = h.normal * (0.5 * set_.skin);
        SweepHit back;
        stats_.sweeps++;
        p += isect_.sweepSphere(scene, p, r, away, opt_, back) ? away * back.t : away;
        // What is left, without its part into the surface; if that would go into the surface met before
        // (a wedge, a corner), along the crease of the two.
        motion *= 1.0 - h.t;
        const double into = glm::dot(motion, h.normal);
        if (into < 0.0) motion -= h.normal * into;
        if (k > 0 && glm::dot(motion, prev) < 0.0) {
            const dvec3 crease = glm::cross(prev, h.normal);
            const double cl = glm::length(crease);
            motion = cl > eps::kParallel ? crease * (glm::dot(motion, crease) / (cl * cl)) : dvec3(0.0);
        }
        prev = h.normal;
    }
    return p;
}

dvec3 ViewpointCollider::move(const Scene& scene, const dvec3& from, const dvec3& step) {
    if (!isFinite(from) || !isFinite(step))
        throw std::invalid_argument("ViewpointCollider::move(): the position or the step is not finite");
    stats_ = ViewpointStats{};
    if (!set_.groundFollow) return slide(scene, from, step);
    // Walk across, then settle on the surface below: up a stair no higher than maxClimb, down at most
    // maxFall per step. Both moves are swept like any other.
    const dvec3 across = step - up_ * glm::dot(step, up_);
    dvec3 p = slide(scene, from, across);
    const double reach = set_.eyeHeight + set_.maxFall;
    Hit below;
    QueryOptions probe = opt_;
    const dvec3 top = p + up_ * set_.maxClimb;
    stats_.grounded = isect_.intersect(scene, Ray{top, -up_, reach + set_.maxClimb}, probe, below);
    const double target =
        stats_.grounded ? glm::dot(below.point, up_) + set_.eyeHeight : glm::dot(p, up_) - set_.maxFall;
    const double dz = std::max(target - glm::dot(p, up_), -set_.maxFall);
    return slide(scene, p, up_ * dz);
}

}  // namespace sg
