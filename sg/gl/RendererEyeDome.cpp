// Renderer: eye-dome lighting (Boucheny 2009, as Potree's EDL and CesiumJS's PointCloudEyeDomeLighting have it): the
// frame's depth is copied into a texture and a full-screen pass darkens each pixel whose neighbours lie in front of
// it, so that shapes read without normals. The shade multiplies the frame's colour through blending (dst x src), so
// the colour is never copied.
#include "sg/gl/Renderer.h"
#include "sg/gl/internal/DepthTarget.h"
#include "sg/gl/internal/EyeDome.h"
#include "sg/gl/internal/GlProgram.h"

#include <GL/gl.h>
#include <GL/glext.h>

namespace sg {

namespace {

// One triangle that covers the viewport, made from gl_VertexID: no vertex buffer.
const char* const kVertex = R"(#version 330 core
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// uProj: the projection's (z, w) rows' depth terms (P[2][2], P[3][2], P[2][3], P[3][3]), which alone give the eye
// depth of a window depth for any perspective or orthographic projection. Background: the clear depth (classic: 1,
// compared with a margin because 24-bit depth may not come back as exactly 1.0; reverse: 0). Background neighbours
// count as not in front (Potree's; CesiumJS drops them from the mean, which shades single points more).
const char* const kFragment = R"(#version 330 core
uniform sampler2D uDepth;
uniform ivec2 uOrigin;
uniform vec4 uProj;
uniform bool uReverse;
uniform float uStrength;
uniform float uRadius;
out vec4 fragColor;

float depthAt(ivec2 p) {
    return texelFetch(uDepth, clamp(p, ivec2(0), textureSize(uDepth, 0) - 1), 0).r;
}
bool background(float d) { return uReverse ? d <= 0.0 : d >= 0.99999976; }
float log2Distance(float d) {
    float ndc = uReverse ? d : 2.0 * d - 1.0;
    float z = (uProj.y - ndc * uProj.w) / (ndc * uProj.z - uProj.x);
    return log2(max(-z, 1e-30));
}
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy) - uOrigin;
    float d = depthAt(p);
    if (background(d)) discard;
    float here = log2Distance(d);
    float sum = 0.0;
    for (int i = 0; i < 8; ++i) {
        float a = float(i) * 0.78539816;
        float n = depthAt(p + ivec2(round(uRadius * vec2(cos(a), sin(a)))));
        if (!background(n)) sum += max(0.0, here - log2Distance(n));
    }
    fragColor = vec4(vec3(exp(-uStrength * 300.0 * sum / 8.0)), 1.0);
}
)";

}  // namespace

EyeDome::EyeDome() {
    program_ = buildGlProgram(kVertex, kFragment, "Renderer: eye-dome lighting");
    uDepth_ = glGetUniformLocation(program_, "uDepth");
    uOrigin_ = glGetUniformLocation(program_, "uOrigin");
    uProj_ = glGetUniformLocation(program_, "uProj");
    uReverse_ = glGetUniformLocation(program_, "uReverse");
    uStrength_ = glGetUniformLocation(program_, "uStrength");
    uRadius_ = glGetUniformLocation(program_, "uRadius");
    glGenVertexArrays(1, &vao_);  // a core context draws nothing without one, even with no attributes
}

EyeDome::~EyeDome() {
    if (depth_) glDeleteTextures(1, &depth_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteProgram(program_);
}

// The depth texture in the format of the frame's depth (24-bit fixed or 32-bit float), so that the copy converts
// nothing; remade when the viewport's size or the depth mode changes.
void EyeDome::resize(int width, int height, bool reverse) {
    if (depth_ && width == width_ && height == height_ && reverse == reverse_) return;
    if (depth_) glDeleteTextures(1, &depth_);
    glGenTextures(1, &depth_);
    glBindTexture(GL_TEXTURE_2D, depth_);
    glTexImage2D(GL_TEXTURE_2D, 0, reverse ? GL_DEPTH_COMPONENT32F : GL_DEPTH_COMPONENT24, width, height, 0,
                 GL_DEPTH_COMPONENT, reverse ? GL_FLOAT : GL_UNSIGNED_INT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // no mipmaps: else incomplete
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);  // depth values, not comparisons
    width_ = width;
    height_ = height;
    reverse_ = reverse;
}

bool EyeDome::apply(const Frame& f) {
    GLint samples = 0, readFbo = 0;
    glGetIntegerv(GL_SAMPLE_BUFFERS, &samples);  // of the bound draw framebuffer: a multisampled one cannot be copied
    if (samples > 0) return false;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo);
    glActiveTexture(GL_TEXTURE0);
    resize(f.width, f.height, f.reverse);
    glBindTexture(GL_TEXTURE_2D, depth_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, f.depthFbo);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, f.x, f.y, f.width, f.height);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(readFbo));

    glUseProgram(program_);
    glUniform1i(uDepth_, 0);
    glUniform2i(uOrigin_, f.x, f.y);
    const dmat4& p = f.projection;
    glUniform4f(uProj_, float(p[2][2]), float(p[3][2]), float(p[2][3]), float(p[3][3]));
    glUniform1i(uReverse_, f.reverse ? 1 : 0);
    glUniform1f(uStrength_, f.strength);
    glUniform1f(uRadius_, f.radius);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ZERO, GL_SRC_COLOR);  // colour x shade; alpha x 1
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glUseProgram(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    return true;
}

void Renderer::eyeDomePass(const Target& t, const Camera& camera) {
    const PointShading& s = pointShading_;
    if (!s.eyeDome || s.eyeDomeStrength <= 0.0f) return;    // strength 0 would multiply by exactly 1
    if (!eyeDome_) eyeDome_ = std::make_unique<EyeDome>();  // compiled on first use: frames without it pay nothing
    EyeDome::Frame f;
    f.x = t.viewport.x;
    f.y = t.viewport.y;
    f.width = t.viewport.width;
    f.height = t.viewport.height;
    f.depthFbo = t.reverse ? depthTarget_->framebuffer() : t.drawFbo;
    f.reverse = t.reverse;
    f.projection = t.reverse ? camera.reverseZProjection() : camera.projection();
    f.strength = s.eyeDomeStrength;
    f.radius = s.eyeDomeRadius;
    eyeDome_->apply(f);
}

}  // namespace sg
