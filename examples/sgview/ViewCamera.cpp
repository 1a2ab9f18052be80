#include "sgview/ViewCamera.h"

#include <algorithm>
#include <cmath>

namespace sgview {

using namespace sg;

Box sceneBound(const Scene& scene, bool* valid) {
    const FlatImage& img = scene.image();
    const bool ok = img.size() > 0 && !(img.flags[0] & (FlatImage::kEmpty | FlatImage::kInvalid));
    if (valid) *valid = ok;
    return ok ? img.box(0) : Box{dvec3(-1.0), dvec3(1.0)};
}

Camera autoCamera(const Box& bound, const dvec3& up, int width, int height) {
    const bool zUp = std::abs(up.z) >= std::abs(up.y);
    const dvec3 u = zUp ? dvec3(0, 0, 1) : dvec3(0, 1, 0);
    const dvec3 right(1, 0, 0), front = zUp ? dvec3(0, -1, 0) : dvec3(0, 0, 1);
    const dvec3 toEye = glm::normalize(right + front + 0.8 * u);
    // View axes: x right, y up, z toward the eye. A corner p (relative to the centre) is in view from
    // distance d when |x| <= (d - z) tan(half fov x) and |y| <= (d - z) tan(half fov y).
    const dvec3 zAxis = toEye, xAxis = glm::normalize(glm::cross(u, zAxis)), yAxis = glm::cross(zAxis, xAxis);
    const double aspect = double(width) / double(height);
    const double ty = std::tan(glm::radians(kFovY) / 2), tx = ty * aspect;
    const dvec3 c = bound.center(), h = bound.halfExtent();
    double d = 0.0;
    for (int k = 0; k < 8; ++k) {
        const dvec3 p((k & 1 ? h.x : -h.x), (k & 2 ? h.y : -h.y), (k & 4 ? h.z : -h.z));
        const double x = glm::dot(p, xAxis), y = glm::dot(p, yAxis), z = glm::dot(p, zAxis);
        d = std::max({d, z + std::abs(x) / tx, z + std::abs(y) / ty});
    }
    d = std::max(d * 1.05, 1e-3);  // a margin around the scene
    return specCamera({c + d * toEye, c, u}, bound, width, height);
}

Camera specCamera(const CameraSpec& spec, const Box& bound, int width, int height) {
    return common::fittedCamera(spec.eye, spec.center, spec.up, bound, width, height);
}

Camera startCamera(const Options& o, const Box& bound, const dvec3& up) {
    return o.camera ? specCamera(*o.camera, bound, o.width, o.height) : autoCamera(bound, up, o.width, o.height);
}

}  // namespace sgview
