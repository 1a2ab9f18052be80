#include "sg/gl/internal/RendererErrors.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdio>
#include <stdexcept>

namespace sg {

#ifndef NDEBUG
namespace {

const char* errorName(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        default: return "unknown GL error";
    }
}

}  // namespace

void checkGl(const char* fn, const char* what) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) return;
    while (glGetError() != GL_NO_ERROR) {
    }
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(e));
    throw std::runtime_error(std::string(fn) + ": " + errorName(e) + " (" + code + ") " + what);
}

void drainGl() {
    while (glGetError() != GL_NO_ERROR) {
    }
}
#endif

std::string describe(const Renderer::Viewport& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.width) + "x" +
           std::to_string(v.height) + ")";
}

}  // namespace sg
