// The value an LOD's ranges are compared with, shared by the cull and the intersection traversal so that a
// pick sees the level that is drawn: the eye's distance to the LOD's centre times the LOD scale, or (pixel
// size mode) its bound's projected diameter in pixels divided by it.
// Internal header: not installed (CMakeLists.txt, SGKIT_INTERNAL_HEADERS); its shape may change freely.
#pragma once
#include "nodes/LOD.h"
#include "sg/core/Camera.h"
#include "sg/scene/FlatImage.h"

#include <cassert>
#include <cmath>

namespace sg {

// Entry i of `img` is an LOD. `rigid`: image coordinates are the world's shifted, the eye at `eyeImg` in them;
// otherwise (below a scaled Instance) `imgToEye` takes image coordinates to the eye's, and `scale` is the
// frame's scale of lengths. `cam` gives the pixels of a pixel-size LOD; a distance LOD needs none (null).
// `lod` is the LOD's (or a PagedLOD's) centre and mode, entry i its bound.
inline double lodValue(const FlatImage& img, const FlatImage::Lod& lod, uint32_t i, bool rigid, const dvec3& eyeImg,
                       const dmat4& imgToEye, double scale, const Camera* cam, double lodScale) {
    double dist;
    if (rigid) {  // measure in image coordinates
        const double dx = lod.cx - eyeImg.x, dy = lod.cy - eyeImg.y, dz = lod.cz - eyeImg.z;
        dist = std::sqrt(dx * dx + dy * dy + dz * dz);
    } else {  // through the frame
        dist = glm::length(dvec3(imgToEye * dvec4(lod.cx, lod.cy, lod.cz, 1.0)));
    }
    // The LOD scale makes everything look farther (scale > 1: coarser levels sooner), as Performer's.
    if (lod.mode != uint8_t(LOD::Mode::PixelSize)) return dist * lodScale;
    assert(cam && "lodValue(): a pixel-size LOD needs a camera");
    return cam->pixelSize(2.0 * img.r[i] * scale, dist) / lodScale;
}

inline double lodValue(const FlatImage& img, uint32_t i, bool rigid, const dvec3& eyeImg, const dmat4& imgToEye,
                       double scale, const Camera* cam, double lodScale) {
    return lodValue(img, img.lods[img.aux[i]], i, rigid, eyeImg, imgToEye, scale, cam, lodScale);
}

}  // namespace sg
