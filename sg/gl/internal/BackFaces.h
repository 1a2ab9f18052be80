// Which draw items may skip their back faces: those no eye ray can meet back-first. Internal header: not installed
// (an internal/ folder, cmake/LayerCheck.cmake).
//
// A ray from an eye outside a closed mesh (Mesh::closed()) enters a solid before it leaves one, so the first face it
// meets faces the eye; drawn opaque with the depth test, every back face lies behind a front face of the same item,
// and skipping them changes no pixel. That holds while the eye is outside the item's bound and the near plane does
// not cut the item (a cut opens the solid and shows its inside), the item is drawn opaque (no alpha cutoff, no
// blending, no dissolve), and its matrix keeps the winding (a mirror turns the front faces back). An item drawn in part
// qualifies only when the part holds every triangle that reaches the screen (DrawList::Part::coversScreen: the cull's
// screen-rect parts), so that the front face in front of each back face on screen is drawn with it.
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/DrawList.h"

#include <algorithm>
#include <cmath>

namespace sg {

// How far from the eye the near plane reaches: the farthest corner of the near rectangle. Negative for a camera
// without an eye point (orthographic), where no item qualifies.
inline double nearPlaneReach(const Camera& camera) {
    if (!camera.perspective()) return -1.0;
    const dmat4 inv = glm::inverse(camera.projection());
    double reach = 0.0;
    for (int c = 0; c < 4; ++c) {
        const dvec4 p = inv * dvec4(c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, -1.0, 1.0);
        reach = std::max(reach, glm::length(dvec3(p) / p.w));
    }
    return std::isfinite(reach) ? reach : -1.0;
}

// Whether the item, drawn with material mat and no dissolve, may skip its back faces (see above). reach:
// nearPlaneReach() of the frame's camera; the item's matrix is relative to the eye.
inline bool backFacesHidden(const DrawItem& item, const Material* mat, double reach) {
    if (reach < 0.0 || !item.mesh->closed() || (mat && (mat->alphaCutoff > 0.0f || mat->blend))) return false;
    const glm::mat3 m(item.model);
    if (!(glm::determinant(m) > 0.0f)) return false;
    // The mesh's box about the eye: centre and half extent under the matrix (as GL transforms its corners).
    const Box& b = item.mesh->box();
    const dvec3 c = dvec3(item.model * vec4(vec3(b.center()), 1.0f)), h = b.halfExtent();
    double d2 = 0.0, size = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double e = std::abs(m[0][i]) * h.x + std::abs(m[1][i]) * h.y + std::abs(m[2][i]) * h.z;
        const double gap = std::max(std::abs(c[i]) - e, 0.0);
        d2 += gap * gap;
        size += std::abs(c[i]) + e;
    }
    // Float rounding of the matrix and the positions, as GL does it: a margin well beyond it.
    const double margin = reach * 1e-3 + size * 1e-5;
    return d2 > (reach + margin) * (reach + margin);
}

}  // namespace sg
