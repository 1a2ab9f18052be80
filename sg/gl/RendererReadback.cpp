// Renderer: what is read back from GL after a draw: the time the GPU took, the pixels and the depth.
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/DepthTarget.h"
#include "sg/gl/internal/GlEntryPoints.h"
#include "sg/gl/internal/RendererErrors.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace sg {

double Renderer::gpuMs() {
    if (timePending_) {
        GLuint64 ns = 0;
        queryObjectUi64()(timeQuery_, GL_QUERY_RESULT, &ns);
        gpuMs_ = double(ns) * 1e-6;
        timePending_ = false;
    }
    return timeQuery_ ? gpuMs_ : -1.0;
}

void Renderer::finish() const { glFinish(); }

Image Renderer::readColor() const {
    GLint vp[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_VIEWPORT, vp);
    return readColor(Viewport{vp[0], vp[1], vp[2], vp[3]});
}

Image Renderer::readColor(const Viewport& rect) const {
    if (rect.width <= 0 || rect.height <= 0 || rect.x < 0 || rect.y < 0)
        throw std::invalid_argument("Renderer::readColor(): rectangle " + describe(rect) +
                                    (rect.width <= 0 || rect.height <= 0 ? " has no area" : " has a negative corner"));
    Image img;
    img.width = rect.width;
    img.height = rect.height;
    const size_t row = size_t(img.width) * 4u;
    std::vector<uint8_t> tmp(row * size_t(img.height));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(rect.x, rect.y, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, tmp.data());
    checkGl("Renderer::readColor()", "from glReadPixels");
    img.rgba.resize(tmp.size());
    for (int y = 0; y < img.height; ++y)  // GL's first row is the bottom one
        std::memcpy(&img.rgba[size_t(y) * row], &tmp[size_t(img.height - 1 - y) * row], row);
    return img;
}

std::vector<float> Renderer::readDepth() const {
    GLint vp[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_VIEWPORT, vp);
    const size_t w = size_t(vp[2]), h = size_t(vp[3]);
    std::vector<float> tmp(w * h), out(w * h);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    GLint readTarget = 0;
    if (lastReverseZ_) {  // the depth is in the renderer's framebuffer, not the target's
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readTarget);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, depthTarget_->framebuffer());
    }
    glReadPixels(vp[0], vp[1], vp[2], vp[3], GL_DEPTH_COMPONENT, GL_FLOAT, tmp.data());
    if (lastReverseZ_) glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(readTarget));
    checkGl("Renderer::readDepth()", "from glReadPixels");
    for (size_t y = 0; y < h; ++y) std::memcpy(&out[y * w], &tmp[(h - 1 - y) * w], w * sizeof(float));
    return out;
}

}  // namespace sg
