#include "common/FittedCamera.h"

#include <algorithm>

namespace common {

using namespace sg;

void clipPlanes(const Box& bound, const dvec3& eye, double& zNear, double& zFar) {
    const double r = std::max(glm::length(bound.halfExtent()), 1e-6);
    const double d = glm::length(eye - bound.center());
    zFar = (d + r) * 1.01;
    zNear = std::max((d - r) * 0.99, zFar * 1e-4);
}

Camera fittedCamera(const dvec3& eye, const dvec3& center, const dvec3& up, const Box& bound, int width, int height) {
    double zNear = 0.0, zFar = 0.0;
    clipPlanes(bound, eye, zNear, zFar);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(kFovY, double(width) / double(height), zNear, zFar);
    cam.setLookAt(eye, center, up);
    return cam;
}

}  // namespace common
