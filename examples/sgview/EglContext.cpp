#include "sgview/EglContext.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sgview {

namespace {

std::string eglError(const char* step) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(eglGetError()));
    return std::string("EglContext::EglContext(): ") + step + " failed (EGL error " + code + ")";
}

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const size_t n = std::strlen(name);
    for (const char* p = std::strstr(list, name); p; p = std::strstr(p + n, name))
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

// Mesa's surfaceless platform needs neither a display server nor a GPU (llvmpipe); else the default display.
EGLDisplay openDisplay() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (hasExtension(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d != EGL_NO_DISPLAY) return d;
    }
    return eglGetDisplay(EGL_DEFAULT_DISPLAY);
}

}  // namespace

EglContext::EglContext(int width, int height) {
    if (width <= 0 || height <= 0)
        throw std::invalid_argument("EglContext::EglContext(): size " + std::to_string(width) + "x" +
                                    std::to_string(height) + " has no area");
    EGLDisplay d = openDisplay();
    if (d == EGL_NO_DISPLAY) throw std::runtime_error(eglError("eglGetDisplay"));
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor)) throw std::runtime_error(eglError("eglInitialize"));
    const char* ext = eglQueryString(d, EGL_EXTENSIONS);
    if (!hasExtension(ext, "EGL_KHR_surfaceless_context") || !hasExtension(ext, "EGL_KHR_no_config_context")) {
        eglTerminate(d);
        throw std::runtime_error("EglContext::EglContext(): the EGL display has no surfaceless, config-less contexts");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        eglTerminate(d);
        throw std::runtime_error(eglError("eglBindAPI(EGL_OPENGL_API)"));
    }
    const EGLint attribs[] = {
        EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext c = eglCreateContext(d, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (c == EGL_NO_CONTEXT) {
        const std::string err = eglError("eglCreateContext (OpenGL 3.3 core)");
        eglTerminate(d);
        throw std::runtime_error(err);
    }
    if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
        const std::string err = eglError("eglMakeCurrent");
        eglDestroyContext(d, c);
        eglTerminate(d);
        throw std::runtime_error(err);
    }
    display_ = d;
    context_ = c;
    w_ = width;
    h_ = height;
    glGenRenderbuffers(1, &color_);
    glBindRenderbuffer(GL_RENDERBUFFER, color_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenRenderbuffers(1, &depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04x", unsigned(status));
        destroy();
        throw std::runtime_error("EglContext::EglContext(): the " + std::to_string(width) + "x" +
                                 std::to_string(height) + " framebuffer is incomplete (status " + code + ")");
    }
}

EglContext::~EglContext() { destroy(); }

void EglContext::makeCurrent() {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw std::runtime_error(eglError("eglMakeCurrent"));
}

void EglContext::release() {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT))
        throw std::runtime_error(eglError("eglMakeCurrent (release)"));
}

void EglContext::destroy() {
    if (!context_) return;
    glDeleteFramebuffers(1, &fbo_);
    glDeleteRenderbuffers(1, &color_);
    glDeleteRenderbuffers(1, &depth_);
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
    context_ = nullptr;
}

}  // namespace sgview
