#include "sg/paging/CameraMotion.h"

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <stdexcept>

namespace sg {

namespace {

// The rotation from eye axes to world axes: the view's 3x3 inverted (a transpose for the rigid views setLookAt
// makes, and right for any other invertible one).
glm::dmat3 eyeToWorld(const Camera& c) { return glm::inverse(glm::dmat3(c.view())); }

// The rotation vector (axis times angle, the angle in [0, pi]) of rotation matrix r.
dvec3 rotationVector(const glm::dmat3& r) {
    glm::dquat q = glm::quat_cast(r);
    if (q.w < 0.0) q = -q;  // the shorter way round
    const dvec3 v(q.x, q.y, q.z);
    const double s = glm::length(v);
    if (!(s > 0.0)) return dvec3(0.0);
    return v / s * (2.0 * std::atan2(s, q.w));
}

bool finite(const dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

void CameraMotion::observe(const Camera& camera, double time) {
    if (!std::isfinite(time) || (frames_ > 0 && time <= time_)) return;
    const glm::dmat3 toWorld = eyeToWorld(camera);
    const dvec3 eye = camera.eye();
    if (frames_ == 0 || time - time_ > kMaxGapSeconds) {
        frames_ = 1;
        velocity_ = turn_ = dvec3(0.0);
    } else {
        const double dt = time - time_;
        const dvec3 v = (eye - eye_) / dt;
        const dvec3 w = rotationVector(toWorld * glm::inverse(toWorld_)) / dt;
        if (!finite(v) || !finite(w)) {
            frames_ = 1;
            velocity_ = turn_ = dvec3(0.0);
        } else if (frames_ == 1) {
            velocity_ = v;
            turn_ = w;
            frames_ = 2;
        } else {
            const double a = 1.0 - std::exp(-dt / kSmoothingSeconds);
            velocity_ += a * (v - velocity_);
            turn_ += a * (w - turn_);
        }
    }
    time_ = time;
    eye_ = eye;
    toWorld_ = toWorld;
}

std::optional<Camera> CameraMotion::predict(const Camera& camera, double seconds) const {
    if (frames_ < 2 || !(seconds > 0.0) || !std::isfinite(seconds)) return std::nullopt;
    if (velocity_ == dvec3(0.0) && turn_ == dvec3(0.0)) return std::nullopt;
    const dvec3 eye = camera.eye() + velocity_ * seconds;
    glm::dmat3 toWorld = eyeToWorld(camera);
    const dvec3 r = turn_ * seconds;
    const double angle = glm::length(r);
    if (angle > 0.0) toWorld = glm::mat3_cast(glm::angleAxis(std::min(angle, kMaxTurn), r / angle)) * toWorld;
    dmat4 view(glm::inverse(toWorld));
    view[3] = dvec4(-(glm::dmat3(view) * eye), 1.0);
    if (!finite(eye) || !finite(dvec3(view[0])) || !finite(dvec3(view[1])) || !finite(dvec3(view[2])))
        return std::nullopt;
    Camera out = camera;
    try {
        out.setView(view);
    } catch (const std::invalid_argument&) {
        return std::nullopt;  // a view the camera refuses (far beyond double's range): no prediction
    }
    return out;
}

}  // namespace sg
