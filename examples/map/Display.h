// Display: what the map's session draws through: the renderer of the program (OSMesa headless, or a GLFW window),
// kept out of the session so that one session code serves both.
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/DrawList.h"
#include "sg/io/ImageIO.h"

#include <string>

namespace sgmap {

// The map's background: night-blue sea, so that the pastel regions stand out.
constexpr sg::vec4 kSeaColor{0.16f, 0.22f, 0.33f, 1.0f};

class Display {
public:
    virtual ~Display() = default;
    // Draws the list and the overlay text (when not empty), and waits until the frame is drawn.
    virtual void draw(const sg::DrawList& list, const sg::Camera& camera, const std::string& overlay) = 0;
    virtual sg::Image read() = 0;
    // Frees the GPU copies of meshes the last frame did not draw (a level left).
    virtual void releaseUnused() = 0;
};

}  // namespace sgmap
