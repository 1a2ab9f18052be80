// Display: where the map's session draws: the renderer of the program's context (OSMesa headless, or a GLFW window),
// kept out of the session so that one session code serves both.
#pragma once
#include "sg/gl/Renderer.h"

#include <string>

namespace sgmap {

// The map's background: night-blue sea, so that the pastel regions stand out.
constexpr sg::vec4 kSeaColor{0.16f, 0.22f, 0.33f, 1.0f};

class Display {
public:
    virtual ~Display() = default;
    // The renderer of the context (current): the session's viewer draws with it.
    virtual sg::Renderer& renderer() = 0;
    // Makes the context current on the calling thread, or releases it from it: a threaded viewer draws on a
    // thread of its own (sg::ViewerSettings::bindContext).
    virtual void bindContext(bool current) = 0;
    sg::Image read() { return renderer().readColor(); }
};

}  // namespace sgmap
