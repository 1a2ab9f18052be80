// Two pictures of one view, drawn with all back faces and with the renderer skipping those that cannot show
// (Renderer::setBackFaceCulling), compared with their depth buffers. A pixel that differs where the two depths
// differ is wrong: a surface missing, or an inside showing. A pixel that differs where the depths agree is a tie at
// a silhouette edge, where a back face meets its front face at the same point: the picture with all back faces
// shows whichever of the two the rasterizer's rounding put in front; a few per view, on silhouettes. The depths
// agree when their distances from the eye do to 0.1%: a depth d stands for a distance proportional to 1 / (1 - d)
// with classic depth, to 1 / d reversed (Renderer::lastDepthReversed()), near enough for a relative tolerance.
#pragma once
#include "sg/io/ImageIO.h"

#include <cmath>
#include <cstring>
#include <vector>

namespace testutil {

struct BackFaceDiff {
    size_t wrong = 0, ties = 0;
};

inline BackFaceDiff compareBackFaces(const sg::Image& all, const std::vector<float>& depthAll, const sg::Image& culled,
                                     const std::vector<float>& depthCulled, bool reversed = false) {
    BackFaceDiff d;
    const size_t n = std::min(depthAll.size(), depthCulled.size());
    if (all.rgba.size() != culled.rgba.size() || n * 4 != all.rgba.size()) {
        d.wrong = all.rgba.size() / 4 + 1;  // not two pictures of one view
        return d;
    }
    for (size_t i = 0; i < n; ++i) {
        if (std::memcmp(&all.rgba[i * 4], &culled.rgba[i * 4], 4) == 0) continue;
        const double a = depthAll[i], b = depthCulled[i], scale = reversed ? a : 1.0 - a;
        if (std::abs(a - b) <= 1e-3 * scale)
            ++d.ties;
        else
            ++d.wrong;
    }
    return d;
}

}  // namespace testutil
