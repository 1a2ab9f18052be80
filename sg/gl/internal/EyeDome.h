// EyeDome: the renderer's eye-dome lighting pass (PointShading::eyeDome): the frame's depth copied into a texture,
// then a full-screen pass that multiplies each drawn pixel's colour by exp(-300 strength x the mean, over 8
// neighbours `radius` pixels away, of how far each lies in front of the pixel in log2 of the eye distance).
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "sg/core/Math.h"

namespace sg {

// Needs the current GL context of its renderer, alive until the pass is destroyed.
class EyeDome {
public:
    // What a frame's pass needs: the viewport shaded, where its depth is, how depth is stored, and the shading.
    struct Frame {
        int x = 0, y = 0, width = 0, height = 0;  // the viewport, in the framebuffer's pixels
        unsigned depthFbo = 0;                    // the framebuffer holding the frame's depth
        bool reverse = false;                     // reversed [0, 1] depth (near 1), else classic (near 0)
        dmat4 projection{1.0};                    // the projection the frame was drawn with
        float strength = 1.0f, radius = 1.0f;
    };

    // Compiles the pass's program. Throws std::runtime_error (with GL's log) when it does not compile or link.
    EyeDome();
    ~EyeDome();
    EyeDome(const EyeDome&) = delete;
    EyeDome& operator=(const EyeDome&) = delete;

    // Shades f's viewport of the bound draw framebuffer; background pixels (the clear depth) are left alone. Leaves
    // the framebuffer bindings as they were, blending off, the depth test on, no program, vertex array or texture
    // bound (unit 0 active).
    // Returns false, having drawn nothing, where the frame's depth cannot be copied (a multisampled framebuffer).
    bool apply(const Frame& f);

private:
    void resize(int width, int height, bool reverse);

    unsigned program_ = 0, vao_ = 0, depth_ = 0;
    int uDepth_ = -1, uOrigin_ = -1, uProj_ = -1, uReverse_ = -1, uStrength_ = -1, uRadius_ = -1;
    int width_ = 0, height_ = 0;
    bool reverse_ = false;  // the depth texture's format: 32-bit float (reverse) or 24-bit fixed
};

}  // namespace sg
