#include "common/Navigator.h"

#include "common/FittedCamera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace common {

using namespace sg;

namespace {
constexpr double kMaxPitch = 89.0 * M_PI / 180.0;
constexpr double kTurnPerPixel = 0.005;  // radians
}  // namespace

const char* navModeName(NavMode m) {
    switch (m) {
        case NavMode::Trackball: return "trackball";
        case NavMode::Fly: return "fly";
        case NavMode::Walk: return "walk";
    }
    return "?";
}

Navigator::Navigator(const Box& bound, const dvec3& up) : bound_(bound) {
    if (!isFinite(up) || glm::length(up) == 0.0)
        throw std::invalid_argument("Navigator::Navigator(): the up axis must be finite and not zero");
    up_ = glm::normalize(up);
    const dvec3 seed = std::abs(up_.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    a_ = glm::normalize(seed - glm::dot(seed, up_) * up_);
    b_ = glm::cross(up_, a_);
    size_ = std::max(glm::length(bound.halfExtent()), 1e-3);
    speed_ = 0.1 * size_;
    lookAt(bound.center() + dvec3(2.0 * size_) * a_, bound.center());
}

void Navigator::lookAt(const dvec3& eye, const dvec3& center) {
    const dvec3 d = center - eye;
    const double len = glm::length(d);
    eye_ = eye;
    if (!(len > 0.0) || !std::isfinite(len)) return;
    const dvec3 f = d / len;
    pitch_ = std::clamp(std::asin(std::clamp(glm::dot(f, up_), -1.0, 1.0)), -kMaxPitch, kMaxPitch);
    yaw_ = std::atan2(glm::dot(f, b_), glm::dot(f, a_));
    distance_ = len;
}

void Navigator::setMode(NavMode m) {
    // The trackball's centre is where it was left: `distance_` ahead of the eye, whatever the mode did since.
    mode_ = m;
}

dvec3 Navigator::forward() const {
    return std::cos(pitch_) * (std::cos(yaw_) * a_ + std::sin(yaw_) * b_) + std::sin(pitch_) * up_;
}

dvec3 Navigator::right() const { return glm::normalize(glm::cross(forward(), up_)); }

void Navigator::drag(int button, double dx, double dy, int height) {
    if (mode_ == NavMode::Trackball && button != kLeft) {
        // Pan: the centre's plane moves with the cursor.
        const double unitsPerPixel = 2.0 * distance_ * std::tan(glm::radians(kFovY) / 2) / std::max(height, 1);
        const dvec3 v = glm::cross(right(), forward());
        eye_ += (-dx * right() + dy * v) * unitsPerPixel;
        return;
    }
    if (button != kLeft) return;
    const dvec3 c = center();
    yaw_ -= dx * kTurnPerPixel;
    pitch_ = std::clamp(pitch_ - dy * kTurnPerPixel, -kMaxPitch, kMaxPitch);
    if (mode_ == NavMode::Trackball) eye_ = c - distance_ * forward();  // orbit: the centre stays
}

void Navigator::setSpeed(double unitsPerSecond) {
    if (std::isfinite(unitsPerSecond)) speed_ = std::clamp(unitsPerSecond, 1e-4 * size_, 10.0 * size_);
}

void Navigator::scroll(double steps) {
    if (mode_ != NavMode::Trackball) {
        setSpeed(speed_ * std::pow(1.25, steps));
        return;
    }
    const dvec3 c = center();
    distance_ = std::clamp(distance_ * std::pow(0.85, steps), 1e-4 * size_, 100.0 * size_);
    eye_ = c - distance_ * forward();
}

void Navigator::move(const MoveKeys& k, double seconds) {
    if (mode_ == NavMode::Trackball || !(seconds > 0.0)) return;
    const double step = speed_ * (k.fast ? 4.0 : 1.0) * seconds;
    const double ahead = double(k.forward) - double(k.back), side = double(k.right) - double(k.left);
    dvec3 v(0.0);
    if (mode_ == NavMode::Fly) {
        v = ahead * forward() + side * right() + (double(k.up) - double(k.down)) * up_;
    } else {
        const dvec3 level = std::cos(yaw_) * a_ + std::sin(yaw_) * b_;  // the view's heading, horizontal
        v = ahead * level + side * right();
    }
    if (!(glm::length(v) > 0.0)) return;
    const dvec3 d = glm::normalize(v) * step;
    eye_ = mode_ == NavMode::Walk && mover_ ? mover_(eye_, d) : eye_ + d;
}

Navigator::Mover collidingWalk(const Scene& scene, ViewpointCollider& collider) {
    return [&scene, &collider](const dvec3& from, const dvec3& step) { return collider.move(scene, from, step); };
}

ViewpointSettings walkSettings(const Box& bound, const dvec3& up) {
    ViewpointSettings s;
    const double k = std::min(1.0, glm::length(bound.max - bound.min) / 50.0);
    s.radius *= k;
    s.eyeHeight *= k;
    s.maxClimb *= k;
    s.maxFall *= k;
    s.groundFollow = true;
    s.up = up;
    return s;
}

Camera Navigator::camera(int width, int height) const {
    return fittedCamera(eye_, eye_ + forward(), up_, bound_, width, height);
}

}  // namespace common
