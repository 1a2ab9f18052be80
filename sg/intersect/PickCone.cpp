#include "sg/intersect/PickCone.h"

#include "sg/core/Camera.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

PickCone pickCone(const Camera& camera, double pixels) {
    if (!(pixels >= 0.0 && std::isfinite(pixels)))
        throw std::invalid_argument("pickCone(): pixels " + std::to_string(pixels) + " is negative or not finite");
    // pixelsPerUnit(): pixels across a length 1 at distance 1 (perspective, h / (2 tan(fovy / 2))) or anywhere
    // (orthographic).
    const double size = pixels / camera.pixelsPerUnit();
    if (camera.perspective()) return {camera.nearDistance() * size, size};
    return {size, 0.0};
}

}  // namespace sg
