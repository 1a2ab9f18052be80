// Renderer: a draw from start to end: where the frame goes (the bound framebuffer, or ReverseZ's own), its GL
// state, its clear, and the steps in between.
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/DepthTarget.h"
#include "sg/gl/internal/GlEntryPoints.h"
#include "sg/gl/internal/GpuCache.h"
#include "sg/gl/internal/RendererErrors.h"

#include <GL/gl.h>
#include <GL/glext.h>
#ifdef SGKIT_GL_OSMESA
#include <GL/osmesa.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sg {

namespace {

// The size of the framebuffer bound for drawing, where GL tells it: OSMesa's buffer, or a framebuffer object's
// first colour renderbuffer. A window's framebuffer and texture attachments (whose target would have to be bound
// to ask) give 0 x 0.
void drawFramebufferSize(GLuint fbo, int& width, int& height) {
    width = height = 0;
    if (fbo == 0) {
#ifdef SGKIT_GL_OSMESA
        GLint w = 0, h = 0;
        OSMesaGetIntegerv(OSMESA_WIDTH, &w);
        OSMesaGetIntegerv(OSMESA_HEIGHT, &h);
        if (w > 0 && h > 0) width = w, height = h;
#endif
        return;
    }
    GLint type = GL_NONE, name = 0, bound = 0;
    glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                          GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_RENDERBUFFER) return;
    glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                          GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    glGetIntegerv(GL_RENDERBUFFER_BINDING, &bound);
    glBindRenderbuffer(GL_RENDERBUFFER, GLuint(name));
    glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_WIDTH, &width);
    glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_HEIGHT, &height);
    glBindRenderbuffer(GL_RENDERBUFFER, GLuint(bound));
}

}  // namespace

void Renderer::draw(const DrawList& list, const Camera& camera, const vec4& clearColor) {
    // The camera's own viewport is not checked against the framebuffer: GL clips what lies outside, as it always has.
    drawFrame(list, camera, Viewport{0, 0, camera.width(), camera.height()}, clearColor, false);
}

void Renderer::draw(const DrawList& list, const Camera& camera, const Viewport& viewport, const vec4& clearColor) {
    drawFrame(list, camera, viewport, clearColor, true);
}

void Renderer::drawFrame(const DrawList& list, const Camera& camera, const Viewport& viewport, const vec4& clearColor,
                         bool inFramebuffer) {
    const auto t0 = std::chrono::steady_clock::now();
    drainGl();
    Target t = target(viewport, inFramebuffer);
    if (!warming_) lastCamera_ = camera;
    cache_->nextFrame();
    stats_ = RenderStats{};
    buildRuns(list, camera);
    upload();
    if (timeQuery_) glBeginQuery(GL_TIME_ELAPSED, timeQuery_);
    beginFrame(t, camera, clearColor);
    if (!runs_.empty()) drawRuns(list, camera, t.reverse);
    if (afterItems_)
        afterItems_(mat4((t.reverse ? camera.reverseZProjection() : camera.projection()) * camera.viewRotation()),
                    t.reverse);
    eyeDomePass(t, camera);
    endFrame(t);
    if (timeQuery_) {
        glEndQuery(GL_TIME_ELAPSED);
        timePending_ = true;
    }
    checkGl("Renderer::draw()", "after drawing");
    stats_.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Renderer::Target Renderer::target(const Viewport& viewport, bool inFramebuffer) {
    const Viewport& v = viewport;
    if (v.width <= 0 || v.height <= 0 || v.x < 0 || v.y < 0)
        throw std::invalid_argument("Renderer::draw(): viewport " + describe(v) +
                                    (v.width <= 0 || v.height <= 0 ? " has no area" : " has a negative corner"));
    GLint drawFbo = 0, readFbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo);
    Target t;
    t.drawFbo = GLuint(drawFbo);
    t.readFbo = GLuint(readFbo);
    t.viewport = v;
    drawFramebufferSize(t.drawFbo, t.width, t.height);
    const int64_t right = int64_t(v.x) + v.width, top = int64_t(v.y) + v.height;
    if (std::max(right, top) > std::numeric_limits<int>::max())
        throw std::invalid_argument("Renderer::draw(): viewport " + describe(v) + " reaches past any framebuffer");
    if (inFramebuffer && t.width > 0 && (right > t.width || top > t.height))
        throw std::invalid_argument("Renderer::draw(): viewport " + describe(v) + " reaches past the " +
                                    std::to_string(t.width) + "x" + std::to_string(t.height) + " framebuffer");
    return t;
}

// Auto: the far/near ratio of a perspective projection is (a - 1) / (a + 1) for a = proj[2][2]
// (-(f + n) / (f - n)); an infinite far plane (a = -1) or NaN gives ReverseZ, the safer.
bool Renderer::wantsReverseZ(const Camera& camera) const {
    const double a = camera.projection()[2][2];
    return depthMode_ == DepthMode::ReverseZ || (depthMode_ == DepthMode::Auto && camera.perspective() &&
                                                 !(std::abs((a - 1.0) / (a + 1.0)) <= kAutoReverseRatio));
}

// Binds where the frame goes (ReverseZ: the renderer's framebuffer, with float depth, in the target's pixel
// coordinates; its colour goes to the target in endFrame), sets the frame's GL state and clears the viewport.
void Renderer::beginFrame(Target& t, const Camera& camera, const vec4& clearColor) {
    const Viewport& v = t.viewport;
    if (wantsReverseZ(camera)) {
        // As large as the target where its size is known, so that views side by side share one; else as large
        // as the viewports drawn so far.
        const int w = std::max(v.x + v.width, t.width), h = std::max(v.y + v.height, t.height);
        const DepthTarget::Bind bound = depthTarget_->bind(w, h, t.width > 0);
        t.reverse = bound == DepthTarget::Bind::Bound;
        if (bound == DepthTarget::Bind::Unsupported) {  // a driver without float depth attachments
            reverseZSupported_ = false;
            depthMode_ = DepthMode::Classic;
        }
        if (!t.reverse) {  // drawn into directly: the bindings as they were (a failed setup may move them)
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.drawFbo);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, t.readFbo);
        }
    }
    lastReverseZ_ = t.reverse;
    if (t.reverse) clipControl()(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glViewport(v.x, v.y, v.width, v.height);
    glScissor(v.x, v.y, v.width, v.height);
    glEnable(GL_SCISSOR_TEST);  // the clear too: glClear ignores the viewport
    glDisable(GL_CULL_FACE);    // per run (Run::cullBack)
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(t.reverse ? GL_GREATER : GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(clearColor.r, clearColor.g, clearColor.b, clearColor.a);
    glClearDepth(t.reverse ? 0.0 : 1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

// Back to GL's defaults for whatever draws next; ReverseZ: the viewport's colour to the framebuffer bound at the
// call, at the same place.
void Renderer::endFrame(const Target& target) {
    glDisable(GL_SCISSOR_TEST);
    if (!target.reverse) return;
    clipControl()(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
    const Viewport& v = target.viewport;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, depthTarget_->framebuffer());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.drawFbo);
    glBlitFramebuffer(v.x, v.y, v.x + v.width, v.y + v.height, v.x, v.y, v.x + v.width, v.y + v.height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.readFbo);
}

}  // namespace sg
