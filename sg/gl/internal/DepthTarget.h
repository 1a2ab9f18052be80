// The renderer's own framebuffer for reverse-Z: RGBA8 colour and a 32-bit float depth buffer, which the
// default framebuffers of OSMesa and GLFW (24-bit fixed depth) do not offer.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once

namespace sg {

// Needs the current GL context of its renderer, alive until the target is destroyed.
class DepthTarget {
public:
    enum class Bind {
        Bound,         // drawn into from now on
        Multisampled,  // the bound draw framebuffer is multisampled: a blit cannot resolve into it
        Unsupported,   // the driver refuses the float depth attachment
    };

    DepthTarget() = default;
    ~DepthTarget() { release(); }
    DepthTarget(const DepthTarget&) = delete;
    DepthTarget& operator=(const DepthTarget&) = delete;

    // Makes the framebuffer width x height (exact), or at least that large (else: it only grows), and binds it for
    // drawing and reading. Unless Bound, the bindings may have moved: the caller binds its target again.
    Bind bind(int width, int height, bool exact);
    void release();
    unsigned framebuffer() const { return fbo_; }

private:
    unsigned fbo_ = 0, color_ = 0, depth_ = 0;
    int width_ = 0, height_ = 0;
};

}  // namespace sg
