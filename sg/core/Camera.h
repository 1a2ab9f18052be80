// Camera: double-precision view and projection, and a viewport; validated when set.
#pragma once
#include "sg/core/Math.h"

#include <algorithm>
#include <array>

namespace sg {

class Camera {
public:
    Camera();
    // Each setter throws std::invalid_argument naming the function and the bad value: non-finite or
    // singular matrices, eye == centre or up parallel to the view, fov outside (0, 180), near <= 0,
    // far <= near, a zero or negative viewport.
    void setLookAt(const dvec3& eye, const dvec3& center, const dvec3& up);
    void setView(const dmat4& view);
    void setPerspective(double fovyDegrees, double aspect, double zNear, double zFar);
    void setProjection(const dmat4& proj);
    void setViewport(int width, int height);

    const dmat4& view() const { return view_; }
    const dmat4& projection() const { return proj_; }
    // projection() with depth reversed for a [0, 1] clip range (glClipControl's GL_ZERO_TO_ONE): the near
    // plane at depth 1, the far plane at 0, x, y and w unchanged. In a float depth buffer the resolution is
    // then relative to the distance at any near/far ratio (docs/architecture.md, "Depth").
    dmat4 reverseZProjection() const;
    const dvec3& eye() const { return eye_; }
    // The view without its translation: what the GPU gets, with geometry placed relative to the eye.
    const dmat4& viewRotation() const { return viewRot_; }
    dvec3 viewDirection() const { return viewDir_; }
    int width() const { return w_; }
    int height() const { return h_; }
    bool perspective() const { return proj_[3][3] == 0.0; }

    // Frustum planes relative to the eye: a world point p is inside when n.(p - eye) + d >= 0 for all.
    const std::array<Plane, 6>& eyePlanes() const { return planes_; }
    // Pixels covered by a length 1 at distance 1 (perspective) or anywhere (orthographic), vertically.
    double pixelsPerUnit() const { return proj_[1][1] * 0.5 * h_; }
    // Pixels across covered by a length `size` facing the eye at `distance` from it. Perspective: the
    // distance is taken as at least the near plane's (nothing nearer is drawn); orthographic: any distance.
    double pixelSize(double size, double distance) const {
        return size * pixelsPerUnit() / (perspective() ? std::max(distance, near_) : 1.0);
    }
    // The near plane's distance from the eye (perspective; at least 1e-9).
    double nearDistance() const { return near_; }
    // The eight frustum corners relative to the eye (near then far; x, y in -1, 1 order).
    std::array<dvec3, 8> eyeCorners() const;

private:
    void derive();
    dmat4 view_{1.0}, proj_{1.0}, viewRot_{1.0};
    dvec3 eye_{0.0}, viewDir_{0.0, 0.0, -1.0};
    std::array<Plane, 6> planes_{};
    double near_ = 1.0;
    int w_ = 640, h_ = 480;
};

}  // namespace sg
