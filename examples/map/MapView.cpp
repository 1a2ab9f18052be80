#include "map/MapView.h"

#include <algorithm>
#include <cmath>

namespace sgmap {

using namespace sg;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

void MapView::clamp() {
    distance = std::isfinite(distance) ? std::clamp(distance, kMinDistance, kMaxDistance) : kMaxDistance;
    for (int i = 0; i < 2; ++i)
        centre[i] = std::isfinite(centre[i]) ? std::clamp(centre[i], -kMaxCentre, kMaxCentre) : 0.0;
}

Camera MapView::camera() const {
    MapView v = *this;
    v.clamp();
    const double t = tiltDegrees * kDeg, distance = v.distance;
    const glm::dvec2 centre = v.centre;
    const dvec3 at(centre, 0.0), eye = at + distance * dvec3(0.0, -std::sin(t), std::cos(t));
    Camera c;
    c.setViewport(width, height);
    // The nearest prism top is about 80 km up; the far plane beyond the map's far edge seen tilted.
    c.setPerspective(fovyDegrees, double(width) / height, std::max(0.01, distance * 0.02), distance * 4.0 + 1000.0);
    c.setLookAt(eye, at, dvec3(0.0, std::cos(t), std::sin(t)));
    return c;
}

double MapView::eyeHeight() const { return distance * std::cos(tiltDegrees * kDeg); }

void MapView::setEyeHeight(double h) {
    distance = h / std::cos(tiltDegrees * kDeg);
    clamp();
}

void MapView::frame(const Box& box, double fill) {
    centre = glm::dvec2(box.center());
    const double tv = std::tan(0.5 * fovyDegrees * kDeg), th = tv * double(width) / height;
    const dvec3 size = box.max - box.min;
    distance = std::max({size.x / (2.0 * th), size.y / (2.0 * tv), 1e-3}) / fill;
    clamp();
}

}  // namespace sgmap
