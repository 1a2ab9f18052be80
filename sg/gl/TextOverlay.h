// TextOverlay: lines of text drawn over the frame at the top left, on a translucent panel (stb_easy_font's
// quads through one small GL 3.3 core shader), for a viewer's stats and help.
#pragma once
#include <string>
#include <vector>

namespace sg {

class TextOverlay {
public:
    // Needs a current OpenGL 3.3 core context. Throws std::runtime_error with the GLSL log when the shader
    // does not build.
    TextOverlay();
    ~TextOverlay();
    TextOverlay(const TextOverlay&) = delete;
    TextOverlay& operator=(const TextOverlay&) = delete;

    // Draws `text` ('\n' between lines, ASCII) into the current framebuffer of width x height pixels, each font
    // pixel `scale` pixels wide. Leaves depth test on and blending off, as the renderer expects them.
    void draw(const std::string& text, int width, int height, float scale = 2.0f);

    // The panel drawn for `text`: the pixels draw() may change, from the top left corner.
    static void panelSize(const std::string& text, float scale, int& width, int& height);

private:
    unsigned program_ = 0, vao_ = 0, vbo_ = 0;
    int uViewport_ = -1;
    std::vector<float> vertices_;  // x, y (pixels), r, g, b, a: six per quad
    std::vector<char> scratch_;    // stb_easy_font's output
};

}  // namespace sg
