#include "sg/gl/TextOverlay.h"

#include "sg/gl/internal/GlProgram.h"

#include <GL/gl.h>
#include <GL/glext.h>
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace sg {

namespace {

const char* kVertex = R"(#version 330 core
layout(location = 0) in vec2 aPixel;
layout(location = 1) in vec4 aColor;
uniform vec2 uViewport;
out vec4 vColor;
void main() {
    gl_Position = vec4(aPixel.x / uViewport.x * 2.0 - 1.0, 1.0 - aPixel.y / uViewport.y * 2.0, 0.0, 1.0);
    vColor = aColor;
}
)";

const char* kFragment = R"(#version 330 core
in vec4 vColor;
out vec4 fragColor;
void main() { fragColor = vColor; }
)";

constexpr float kMargin = 6.0f;  // panel edge to text, in font pixels

}  // namespace

TextOverlay::TextOverlay() {
    program_ = buildGlProgram(kVertex, kFragment, "TextOverlay::TextOverlay()");
    uViewport_ = glGetUniformLocation(program_, "uViewport");
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    const auto colorOffset = reinterpret_cast<const void*>(2 * sizeof(float));
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), colorOffset);
    glBindVertexArray(0);
}

TextOverlay::~TextOverlay() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteProgram(program_);
}

void TextOverlay::panelSize(const std::string& text, float scale, int& width, int& height) {
    std::vector<char> t(text.begin(), text.end());
    t.push_back('\0');
    width = int(std::ceil((float(stb_easy_font_width(t.data())) + 2 * kMargin) * scale));
    height = int(std::ceil((float(stb_easy_font_height(t.data())) + 2 * kMargin) * scale));
}

void TextOverlay::draw(const std::string& text, int width, int height, float scale) {
    std::vector<char> t(text.begin(), text.end());
    t.push_back('\0');
    vertices_.clear();
    auto quad = [&](float x0, float y0, float x1, float y1, const float* c) {
        const float xy[6][2] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y0}, {x1, y1}, {x0, y1}};
        for (const auto& p : xy) vertices_.insert(vertices_.end(), {p[0], p[1], c[0], c[1], c[2], c[3]});
    };
    int pw = 0, ph = 0;
    panelSize(text, scale, pw, ph);
    const float panel[4] = {0.0f, 0.0f, 0.0f, 0.6f}, ink[4] = {1.0f, 0.95f, 0.6f, 1.0f};
    quad(0.0f, 0.0f, float(pw), float(ph), panel);
    // stb_easy_font: 4 vertices per quad of 16 bytes (x, y, z floats, RGBA8), y downward; ~270 bytes a character.
    scratch_.resize(t.size() * 300 + 1024);
    const int quads = stb_easy_font_print(kMargin, kMargin, t.data(), nullptr, scratch_.data(), int(scratch_.size()));
    for (int q = 0; q < quads; ++q) {
        float v0[2], v2[2];  // opposite corners
        std::memcpy(v0, &scratch_[size_t(q) * 64], sizeof v0);
        std::memcpy(v2, &scratch_[size_t(q) * 64 + 32], sizeof v2);
        quad(v0[0] * scale, v0[1] * scale, v2[0] * scale, v2[1] * scale, ink);
    }

    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(program_);
    glUniform2f(uViewport_, float(width), float(height));
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices_.size() * sizeof(float)), vertices_.data(), GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices_.size() / 6));
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

}  // namespace sg
