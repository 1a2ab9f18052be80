// FittedCamera: the perspective camera of an interactive view, its clip planes fitted to the scene's bound
// from wherever the eye is (sgview's views and the navigator's).
#pragma once
#include "sg/core/Camera.h"

namespace common {

constexpr double kFovY = 60.0;

// Near and far planes for an eye: far reaches past the bound's sphere, near is as far out as the sphere
// allows, but at least far / 10^4 (the depth buffer's useful range).
void clipPlanes(const sg::Box& bound, const sg::dvec3& eye, double& zNear, double& zFar);

// Looks from eye at center (up: up) with fov kFovY over width x height, its planes from clipPlanes.
sg::Camera fittedCamera(const sg::dvec3& eye, const sg::dvec3& center, const sg::dvec3& up, const sg::Box& bound,
                        int width, int height);

}  // namespace common
