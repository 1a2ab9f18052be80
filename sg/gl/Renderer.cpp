// Renderer: what the context offers (checked at construction), and the depth strategy asked for.
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/DepthTarget.h"
#include "sg/gl/internal/EyeDome.h"  // eyeDome_'s destructor
#include "sg/gl/internal/GlEntryPoints.h"
#include "sg/gl/internal/GpuCache.h"
#include "sg/gl/internal/RendererErrors.h"
#include "sg/gl/internal/Shaders.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sg {

Renderer::Renderer() {
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    if (!version) throw std::runtime_error("Renderer::Renderer(): no current OpenGL context");
    int major = 0, minor = 0;
    if (std::sscanf(version, "%d.%d", &major, &minor) != 2 || major * 10 + minor < 33)
        throw std::runtime_error(std::string("Renderer::Renderer(): OpenGL 3.3 is needed, the context has ") + version);
    drainGl();

    one_ = link(kVertexShader, kFragmentShader, "Renderer::Renderer()");
    glGenBuffers(1, &instanceVbo_);
    // Anisotropic filtering: core in GL 4.6, an extension before it that nearly every driver has. Not on a
    // software rasterizer, where each extra sample is paid in full, unlike on a GPU's texture units (what it
    // costs: docs/benchmarks.md, "Factory walkthrough").
    const auto* glRenderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string rendererName = glRenderer ? glRenderer : "";
    software_ = rendererName.find("llvmpipe") != std::string::npos ||
                rendererName.find("softpipe") != std::string::npos || rendererName.find("swrast") != std::string::npos;
    float maxAnisotropy = 1.0f;  // 1 when GL has no anisotropic filtering, or rasterizes in software
    GLint extensions = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &extensions);
    for (GLint i = 0; i < extensions && !software_; ++i) {
        const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        if (e && (std::strcmp(e, "GL_EXT_texture_filter_anisotropic") == 0 ||
                  std::strcmp(e, "GL_ARB_texture_filter_anisotropic") == 0)) {
            glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT, &maxAnisotropy);
            break;
        }
    }
    // Reverse-Z needs the [0, 1] clip depth of glClipControl: with GL's [-1, 1] the window transform's
    // 0.5 z + 0.5 rounds away the float buffer's resolution near 0, where the far depths are.
    bool clipControlExt = major * 10 + minor >= 45;
    for (GLint i = 0; i < extensions && !clipControlExt; ++i) {
        const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        clipControlExt = e && std::strcmp(e, "GL_ARB_clip_control") == 0;
    }
    reverseZSupported_ = clipControlExt && clipControl() != nullptr;
    glEnable(GL_PROGRAM_POINT_SIZE);  // points are sized by the vertex stage (kShadePoint)
    // Lines wider than a pixel: glLineWidth where the context draws them (Mesa's core contexts: up to 255), a
    // geometry stage where it does not: a forward-compatible context (what GlfwWindow asks for) takes no width
    // above 1.
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    GLfloat lineRange[2] = {1.0f, 1.0f};
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, lineRange);
    maxLineWidth_ = (flags & GL_CONTEXT_FLAG_FORWARD_COMPATIBLE_BIT) ? 1.0f : std::max(1.0f, lineRange[1]);
    depthMode_ = reverseZSupported_ ? DepthMode::Auto : DepthMode::Classic;
    try {
        checkGl("Renderer::Renderer()", "after compiling the shaders");
    } catch (...) {
        glDeleteBuffers(1, &instanceVbo_);
        glDeleteProgram(one_.id);
        throw;
    }
    // Timer queries are core in GL 3.3 (ARB_timer_query); a driver may still report no counter bits.
    GLint bits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
    if (glGetError() == GL_NO_ERROR && bits > 0 && queryObjectUi64()) glGenQueries(1, &timeQuery_);
    cache_ = std::make_unique<GpuCache>(instanceVbo_, maxAnisotropy);
    depthTarget_ = std::make_unique<DepthTarget>();
}

Renderer::~Renderer() {
    cache_.reset();
    depthTarget_.reset();
    eyeDome_.reset();
    glDeleteBuffers(1, &instanceVbo_);
    if (jointBuffer_) glDeleteBuffers(1, &jointBuffer_);
    if (timeQuery_) glDeleteQueries(1, &timeQuery_);
    glDeleteProgram(one_.id);
    for (auto& [features, p] : variants_) glDeleteProgram(p.id);
}

void Renderer::setDepthMode(DepthMode mode) {
    if (mode != DepthMode::Classic && !reverseZSupported_)
        throw std::invalid_argument(
            "Renderer::setDepthMode(): reverse-Z needs glClipControl (OpenGL 4.5 or GL_ARB_clip_control), which "
            "this context lacks");
    depthMode_ = mode;
}

void Renderer::setPointShading(const PointShading& shading) {
    auto positive = [](float v, const char* name) {
        if (!(v > 0.0f) || !std::isfinite(v))
            throw std::invalid_argument(std::string("Renderer::setPointShading(): ") + name + " " + std::to_string(v) +
                                        " is not finite and positive");
    };
    positive(shading.pointSize, "pointSize");
    positive(shading.maxPointSize, "maxPointSize");
    positive(shading.spacingScale, "spacingScale");
    positive(shading.lineWidth, "lineWidth");
    positive(shading.eyeDomeRadius, "eyeDomeRadius");
    if (!(shading.eyeDomeStrength >= 0.0f) || !std::isfinite(shading.eyeDomeStrength))
        throw std::invalid_argument("Renderer::setPointShading(): eyeDomeStrength " +
                                    std::to_string(shading.eyeDomeStrength) + " is not finite and not negative");
    pointShading_ = shading;
}

}  // namespace sg
