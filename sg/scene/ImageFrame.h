// ImageFrame: where a flat image is as the eye sees it this frame (the scene's own, a prototype's at one
// Instance placement, a paged detail's): the one description the cull, the intersection traversal and the
// LOD budget share.
#pragma once
#include "sg/scene/FlatImage.h"

namespace sg {

struct ImageFrame {
    const FlatImage* img = nullptr;
    dmat4 imgToEye{1.0};  // image coordinates -> coordinates relative to the eye (world axes)
    dvec3 eyeImg{0.0};    // the eye in image coordinates
    double scale = 1.0;   // lengths: image units -> world units (at most)
    bool rigid = true;    // imgToEye keeps lengths: distances may be taken in image coordinates

    // The frame of `image` placed by `imgToEye` (affine): the eye, the scale and rigidity worked out from it.
    static ImageFrame make(const FlatImage& image, const dmat4& imgToEye);

    // The eye's distance to the point (x, y, z) of the image, in world units: in image coordinates when the
    // frame is rigid (no matrix product per call), else through the frame.
    double distance(double x, double y, double z) const {
        if (rigid) {
            const double dx = x - eyeImg.x, dy = y - eyeImg.y, dz = z - eyeImg.z;
            return std::sqrt(dx * dx + dy * dy + dz * dz);
        }
        return glm::length(dvec3(imgToEye * dvec4(x, y, z, 1.0)));
    }
};

// Whether `t` keeps lengths (A^T A == I within eps::kRigid for its linear part A): distances may then be taken in
// the frame it maps from.
bool isRigid(const dmat4& t);

}  // namespace sg
