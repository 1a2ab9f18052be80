#include "sg/gl/internal/GlProgram.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <stdexcept>
#include <string>

namespace sg {

namespace {

std::string shaderLog(GLuint s) {
    GLint len = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(len > 0 ? len : 1), '\0');
    glGetShaderInfoLog(s, GLsizei(log.size()), nullptr, log.data());
    return log.c_str();
}

GLuint compile(GLenum type, const char* src, const char* name, const char* who) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = GL_FALSE;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (ok == GL_TRUE) return s;
    const std::string log = shaderLog(s);
    glDeleteShader(s);
    throw std::runtime_error(std::string(who) + ": the " + name + " shader does not compile: " + log);
}

}  // namespace

unsigned buildGlProgram(const char* vertexSource, const char* fragmentSource, const char* who,
                        const char* geometrySource) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertexSource, "vertex", who);
    GLuint fs = 0, gs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragmentSource, "fragment", who);
        if (geometrySource) gs = compile(GL_GEOMETRY_SHADER, geometrySource, "geometry", who);
    } catch (...) {
        glDeleteShader(vs);
        if (fs) glDeleteShader(fs);
        throw;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    if (gs) glAttachShader(program, gs);
    glLinkProgram(program);
    glDeleteShader(vs);  // flagged: freed with the program
    glDeleteShader(fs);
    if (gs) glDeleteShader(gs);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok == GL_TRUE) return program;
    GLint len = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(len > 0 ? len : 1), '\0');
    glGetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
    glDeleteProgram(program);
    throw std::runtime_error(std::string(who) + ": the shaders do not link: " + log.c_str());
}

}  // namespace sg
