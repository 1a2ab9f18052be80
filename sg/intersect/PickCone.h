// PickCone: the cone about a pixel's ray (pixelRay()) within which points and lines are picked: a radius in pixels
// of a view made the QueryOptions' coneWidth and coneSlope.
#pragma once

namespace sg {

class Camera;

struct PickCone {
    double coneWidth = 0.0, coneSlope = 0.0;
};

// The cone of `pixels` pixels of the camera's image about a ray from pixelRay(). Perspective: the angle of that many
// pixels at the image's centre (slope = pixels * 2 tan(fovy / 2) / height), and the width that angle has at the near
// plane, where pixelRay() starts. Orthographic: that many pixels' width everywhere, slope 0. Throws
// std::invalid_argument for a negative or non-finite `pixels`.
PickCone pickCone(const Camera& camera, double pixels);

}  // namespace sg
