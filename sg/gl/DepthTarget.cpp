#include "sg/gl/internal/DepthTarget.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>

namespace sg {

DepthTarget::Bind DepthTarget::bind(int width, int height, bool exact) {
    GLint samples = 0;
    glGetIntegerv(GL_SAMPLE_BUFFERS, &samples);  // of the bound draw framebuffer
    if (samples > 0) return Bind::Multisampled;
    if (!exact) {
        width = std::max(width, width_);
        height = std::max(height, height_);
    }
    if (fbo_ == 0 || width != width_ || height != height_) {
        release();
        glGenRenderbuffers(1, &color_);
        glBindRenderbuffer(GL_RENDERBUFFER, color_);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
        glGenRenderbuffers(1, &depth_);
        glBindRenderbuffer(GL_RENDERBUFFER, depth_);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
        glBindRenderbuffer(GL_RENDERBUFFER, 0);
        glGenFramebuffers(1, &fbo_);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            release();
            return Bind::Unsupported;
        }
        width_ = width;
        height_ = height;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    return Bind::Bound;
}

void DepthTarget::release() {
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (color_) glDeleteRenderbuffers(1, &color_);
    if (depth_) glDeleteRenderbuffers(1, &depth_);
    fbo_ = color_ = depth_ = 0;
    width_ = height_ = 0;
}

}  // namespace sg
