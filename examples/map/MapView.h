// MapView: where the map is looked at from: a point of the map's plane, a distance and a tilt towards the north
// (the prisms' walls show); the camera, and the framing of a region.
#pragma once
#include "sg/core/Camera.h"

namespace sgmap {

struct MapView {
    glm::dvec2 centre{0.0};     // the point looked at, on the plane z = 0 (kilometres)
    double distance = 30000.0;  // from the eye to it
    double tiltDegrees = 25.0;  // from straight down, looking north
    double fovyDegrees = 45.0;
    int width = 1280, height = 720;

    // The view is kept where a camera can be made from it: the distance within [kMinDistance, kMaxDistance]
    // and the centre within kMaxCentre of the origin (a zoom by 1e300, a goto to 1e300 km would otherwise leave
    // no camera, and every later command failing).
    static constexpr double kMinDistance = 0.05, kMaxDistance = 200000.0, kMaxCentre = 100000.0;
    void clamp();

    // The camera of the view, clamped.
    sg::Camera camera() const;
    // Height of the eye over the plane.
    double eyeHeight() const;
    void setEyeHeight(double h);
    // Looks at the box's centre from the distance at which the box fills `fill` of the window's width or height
    // (whichever it reaches first).
    void frame(const sg::Box& box, double fill);
};

}  // namespace sgmap
