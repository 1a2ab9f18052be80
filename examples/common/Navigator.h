// Navigator: a viewer's eye under trackball, fly and walk navigation (no window or GL: driven by events).
#pragma once
#include "sg/core/Camera.h"
#include "sg/core/Math.h"
#include "sg/intersect/ViewpointCollider.h"

#include <cstdint>
#include <functional>

namespace common {

enum class NavMode : uint8_t { Trackball, Fly, Walk };
const char* navModeName(NavMode m);

struct MoveKeys {
    bool forward = false, back = false, left = false, right = false, down = false, up = false, fast = false;
};

// One orientation (yaw and pitch about the scene's up axis) shared by the three modes, so that switching
// mode never moves the view. Trackball: the eye orbits a centre `distance` ahead of it. Fly: the eye moves
// along its view. Walk: as fly, on the horizontal plane at the eye's height, each step through the walk
// mover when one is set (collidingWalk: walls stop the eye and it slides along them; it follows the ground).
class Navigator {
public:
    enum Button { kLeft = 0, kRight = 1, kMiddle = 2 };  // GLFW's numbering

    // `bound` scales the speeds and gives the clip planes; `up` is the scene's up axis (normalized here).
    // Throws std::invalid_argument for a zero or non-finite up.
    Navigator(const sg::Box& bound, const sg::dvec3& up);

    // Looks from eye toward center (the trackball's centre); the pitch is kept within 89 degrees.
    void lookAt(const sg::dvec3& eye, const sg::dvec3& center);
    NavMode mode() const { return mode_; }
    void setMode(NavMode m);

    // A mouse drag of (dx, dy) pixels in a viewport `height` pixels high. Trackball: left orbits the centre,
    // right or middle pans (the point under the cursor follows it). Fly and walk: left turns the view.
    void drag(int button, double dx, double dy, int height);
    // Wheel steps (positive: up). Trackball: zooms toward the centre; fly and walk: changes the speed.
    void scroll(double steps);
    // Fly and walk: moves for `seconds` with the keys held (shift-like `fast`: 4 times the speed).
    void move(const MoveKeys& keys, double seconds);

    const sg::dvec3& eye() const { return eye_; }
    sg::dvec3 center() const { return eye_ + distance_ * forward(); }
    sg::dvec3 forward() const;
    sg::dvec3 right() const;
    const sg::dvec3& up() const { return up_; }
    double speed() const { return speed_; }
    // Fly and walk: units per second, kept within what scroll() allows (10^-4 to 10 times the bound's radius).
    void setSpeed(double unitsPerSecond);
    double distance() const { return distance_; }
    // Walk steps go through this when set: the eye moves from `from` to what it returns for the wanted step.
    using Mover = std::function<sg::dvec3(const sg::dvec3& from, const sg::dvec3& step)>;
    void setWalkMover(Mover m) { mover_ = std::move(m); }
    // The view as a camera of this viewport, its planes fitted to the bound from the current eye.
    sg::Camera camera(int width, int height) const;

private:
    sg::Box bound_;
    sg::dvec3 up_, a_, b_;  // up and two horizontal axes with a x b = up; yaw 0 looks along a
    NavMode mode_ = NavMode::Trackball;
    sg::dvec3 eye_{0.0};
    double yaw_ = 0.0, pitch_ = 0.0;  // radians
    double distance_ = 1.0;           // trackball: eye to centre
    double speed_ = 1.0;              // fly and walk: units per second
    double size_ = 1.0;               // the bound's radius
    Mover mover_;
};

// A walk mover over `scene` through `collider` (kept by the caller): collidable geometry stops the eye and
// it slides along it; with the collider's ground following, the eye keeps its height above the ground.
Navigator::Mover collidingWalk(const sg::Scene& scene, sg::ViewpointCollider& collider);
// Collider settings for walking through a scene of this bound: a person in a scene of metres (eye 1.7 m,
// radius 0.3 m), scaled down for scenes smaller than 50 units across.
sg::ViewpointSettings walkSettings(const sg::Box& bound, const sg::dvec3& up);

}  // namespace common
