#include "sg/core/Camera.h"

#include <stdexcept>

namespace sg {

Camera::Camera() { setPerspective(60.0, 4.0 / 3.0, 1.0, 1000.0); }

static std::string num(double v) { return std::to_string(v); }

void Camera::setLookAt(const dvec3& eye, const dvec3& center, const dvec3& up) {
    if (!isFinite(eye) || !isFinite(center) || !isFinite(up))
        throw std::invalid_argument("Camera::setLookAt(): eye, centre and up must be finite");
    const dvec3 f = center - eye;
    if (!(glm::length(f) > 0.0)) throw std::invalid_argument("Camera::setLookAt(): eye equals centre");
    if (!(glm::length(glm::cross(glm::normalize(f), up)) > 1e-12))
        throw std::invalid_argument("Camera::setLookAt(): up is zero or parallel to the view direction");
    setView(glm::lookAt(eye, center, up));
}

void Camera::setView(const dmat4& view) {
    const std::string bad = nonFiniteElement(view);
    if (!bad.empty()) throw std::invalid_argument("Camera::setView(): " + bad);
    if (!(std::abs(glm::determinant(view)) > eps::kDegenerate))
        throw std::invalid_argument("Camera::setView(): matrix is singular " + toString(view));
    view_ = view;
    derive();
}

void Camera::setPerspective(double fovy, double aspect, double zNear, double zFar) {
    if (!(fovy > 0.0 && fovy < 180.0))
        throw std::invalid_argument("Camera::setPerspective(): fovy " + num(fovy) + " is not in (0, 180)");
    if (!(aspect > 0.0 && std::isfinite(aspect)))
        throw std::invalid_argument("Camera::setPerspective(): aspect " + num(aspect) + " is not positive");
    if (!(zNear > 0.0 && std::isfinite(zNear)))
        throw std::invalid_argument("Camera::setPerspective(): near " + num(zNear) + " is not positive");
    if (!(zFar > zNear && std::isfinite(zFar)))
        throw std::invalid_argument("Camera::setPerspective(): far " + num(zFar) + " is not beyond near " + num(zNear));
    setProjection(glm::perspective(glm::radians(fovy), aspect, zNear, zFar));
}

void Camera::setProjection(const dmat4& p) {
    const std::string bad = nonFiniteElement(p);
    if (!bad.empty()) throw std::invalid_argument("Camera::setProjection(): " + bad);
    if (!(std::abs(glm::determinant(p)) > eps::kDegenerate))
        throw std::invalid_argument("Camera::setProjection(): projection is degenerate (determinant " +
                                    num(glm::determinant(p)) + ") " + toString(p));
    proj_ = p;
    derive();
}

void Camera::setViewport(int width, int height) {
    if (width <= 0 || height <= 0)
        throw std::invalid_argument("Camera::setViewport(): viewport " + std::to_string(width) + "x" +
                                    std::to_string(height) + " has no area");
    w_ = width;
    h_ = height;
}

void Camera::derive() {
    const dmat4 inv = glm::inverse(view_);
    eye_ = dvec3(inv[3]);
    // view = viewRot * translate(-eye): remove the translation so that it never meets float.
    viewRot_ = view_ * glm::translate(dmat4(1.0), eye_);
    viewRot_[3] = dvec4(0.0, 0.0, 0.0, 1.0);
    viewDir_ = glm::normalize(-dvec3(inv[2]));
    planes_ = frustumPlanes(proj_ * viewRot_);
    near_ = std::max(-planes_[4].d, 1e-9);
}

dmat4 Camera::reverseZProjection() const {
    // Clip depth z' = (w - z) / 2: GL's -1 (near) goes to 1, +1 (far) to 0. In double, so that a near/far
    // ratio of 1e7 keeps its digits in the depth row; for glm::perspective the row is n (z + f) / (f - n).
    dmat4 remap(1.0);
    remap[2][2] = -0.5;
    remap[3][2] = 0.5;
    return remap * proj_;
}

std::array<dvec3, 8> Camera::eyeCorners() const {
    const dmat4 inv = glm::inverse(proj_ * viewRot_);
    std::array<dvec3, 8> c;
    int k = 0;
    for (double z : {-1.0, 1.0})
        for (double y : {-1.0, 1.0})
            for (double x : {-1.0, 1.0}) {
                const dvec4 p = inv * dvec4(x, y, z, 1.0);
                c[size_t(k++)] = dvec3(p) / p.w;
            }
    return c;
}

}  // namespace sg
