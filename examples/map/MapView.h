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

    sg::Camera camera() const;
    // Height of the eye over the plane.
    double eyeHeight() const;
    void setEyeHeight(double h);
    // Looks at the box's centre from the distance at which the box fills `fill` of the window's width or height
    // (whichever it reaches first).
    void frame(const sg::Box& box, double fill);
};

}  // namespace sgmap
