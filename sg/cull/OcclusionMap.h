// OcclusionMap: one frame's hierarchical occlusion map (Zhang et al.): the selected occluders rasterized in
// software into a coverage map over the viewport, its opacity pyramid (averages of 2 x 2 pixels), and a
// depth estimate per map pixel (the farthest depth of the nearest occluder covering it) with its max pyramid.
// A box is occluded when its screen rectangle, tested at the pyramid level whose pixels match its size and
// descending where a pixel is only partly covered, is covered, and its nearest depth lies beyond the
// estimate there.
//
// Conservative when the opacity threshold is 1: a map pixel counts as covered only when it lies entirely
// inside an occluder's projection (front faces, clipped by the near plane) moved inward by the GPU's
// sub-pixel snapping; a box's rectangle is moved outward by as much; an occluder's depth is the farthest
// point of its front faces, moved away by the depth buffer's resolution. Every GPU pixel centre inside a
// covered map pixel then shows an occluder nearer than anything of the box there. Below 1 (approximate), a
// pyramid pixel that much covered counts as covered, so boxes seen only through small holes are culled too.
#pragma once
#include "sg/core/Math.h"
#include "sg/cull/CullSettings.h"

#include <cstdint>
#include <vector>

namespace sg {

class Camera;

class OcclusionMap {
public:
    enum class Result : uint8_t {
        Visible,      // nothing covered under its rectangle: nothing inside it needs testing either
        NotOccluded,  // partly covered or nearer than the occluders: boxes inside it may still be occluded
        Occluded,
    };
    struct Options {
        int width = 256, height = 256;        // powers of two
        float opacity = 1.0f;                 // a pyramid pixel counts as covered at this opacity (1: conservative)
        double marginX = 0.0, marginY = 0.0;  // map pixels: the GPU's snapping, occluder edges moved inward
        double depthMargin = 0.0;             // K: occluder depths moved away by K * depth^2
    };
    // The map's size and threshold from the settings; margins for the camera's viewport (a 64th of a
    // pixel) and depth buffer (8 steps of 24 bits, as the tree). Throws std::invalid_argument naming the
    // bad size or threshold.
    static Options optionsFor(const Camera& cam, const OcclusionSettings& s);

    // Empties the map for the camera (its projection and rotation; geometry is given relative to the eye).
    void reset(const Camera& cam, const Options& o);
    // Adds the front faces of a box occluder: the corners of a parallelepiped relative to the eye (bit 0:
    // x max, bit 1: y max, bit 2: z max, as OcclusionTree::silhouette). False when nothing was covered.
    bool addBox(const dvec3 corners[8]);
    // Adds a convex planar polygon (eye-relative), seen from either side.
    bool addPolygon(const dvec3* vertices, size_t count);
    // Builds the pyramids; call once after the occluders, before the tests.
    void finish();

    // Tests the eye-relative world box [lo, hi].
    Result test(const dvec3& lo, const dvec3& hi) const;
    // Tests the box with these eye-relative corners (any parallelepiped).
    Result test(const dvec3 corners[8]) const;

    bool empty() const { return covered_ == 0; }
    uint64_t coveredPixels() const { return covered_; }
    int levels() const { return int(opacity_.size()); }
    int width(int level) const { return w_[size_t(level)]; }
    int height(int level) const { return h_[size_t(level)]; }
    // A pyramid pixel's opacity (0..1) and depth estimate (0 where nothing is covered), for tests.
    float opacity(int level, int x, int y) const { return opacity_[size_t(level)][size_t(y * w_[size_t(level)] + x)]; }
    float depth(int level, int x, int y) const { return depth_[size_t(level)][size_t(y * w_[size_t(level)] + x)]; }

private:
    struct Pt {
        double x, y;  // map pixels
    };
    // Clips an eye-relative convex polygon by the near plane and projects it to map pixels; false when
    // nothing is left.
    bool project(const dvec3* v, size_t n, std::vector<Pt>& out);
    // Covers the map pixels entirely inside the convex polygon (either orientation), with this depth.
    bool rasterize(std::vector<Pt>& poly, float depth);
    float farDepth(double w) const;
    bool covered(int level, int x0, int y0, int x1, int y1, float zmin) const;

    Options opt_;
    dmat4 viewProj_{1.0};                              // eye-relative world to clip space
    Plane near_{};                                     // eye-relative, moved forward by its rounding
    std::vector<std::vector<float>> opacity_, depth_;  // per level, row-major
    std::vector<int> w_, h_;
    uint64_t covered_ = 0;
    std::vector<dvec3> clip_;  // scratch
    std::vector<Pt> poly_, hull_;
};

}  // namespace sg
