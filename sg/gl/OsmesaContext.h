// OsmesaContext: a headless OpenGL 3.3+ core-profile context that renders into an owned RGBA8 buffer.
#pragma once
#include <cstdint>
#include <vector>

struct osmesa_context;  // from <GL/osmesa.h>, kept out of this header

namespace sg {

class OsmesaContext {
public:
    // Makes the context current. Throws std::invalid_argument when width or height is <= 0, and
    // std::runtime_error when OSMesa cannot create a 3.3 core context or bind the buffer.
    OsmesaContext(int width, int height);
    ~OsmesaContext();
    OsmesaContext(const OsmesaContext&) = delete;
    OsmesaContext& operator=(const OsmesaContext&) = delete;

    // Throws std::runtime_error when OSMesa refuses to bind the buffer.
    void makeCurrent();
    // Releases the context from the calling thread (another thread may then make it current: a viewer's draw
    // thread, ViewerSettings::bindContext). Throws std::runtime_error when OSMesa refuses.
    void release();
    // Reallocates the colour buffer (the depth buffer follows) and makes the context current; the
    // previous contents are lost. Same exceptions as the constructor.
    void resize(int width, int height);
    int width() const { return w_; }
    int height() const { return h_; }

private:
    osmesa_context* ctx_ = nullptr;
    std::vector<uint8_t> buffer_;  // RGBA8, bottom row first (OSMesa's default)
    int w_ = 0, h_ = 0;
};

}  // namespace sg
