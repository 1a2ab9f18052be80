#include "sg/gl/OsmesaContext.h"

#include <GL/osmesa.h>

#include <stdexcept>
#include <string>

namespace sg {

static void checkSize(int width, int height, const char* fn) {
    if (width <= 0 || height <= 0)
        throw std::invalid_argument(std::string(fn) + ": size " + std::to_string(width) + "x" + std::to_string(height) +
                                    " has no area");
}

OsmesaContext::OsmesaContext(int width, int height) {
    checkSize(width, height, "OsmesaContext::OsmesaContext()");
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_STENCIL_BITS,
                           0,
                           OSMESA_ACCUM_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_)
        throw std::runtime_error(
            "OsmesaContext::OsmesaContext(): OSMesa could not create an OpenGL 3.3 core-profile context");
    w_ = width;
    h_ = height;
    buffer_.assign(size_t(width) * size_t(height) * 4u, 0);
    if (!OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
        OSMesaDestroyContext(ctx_);
        ctx_ = nullptr;
        throw std::runtime_error("OsmesaContext::OsmesaContext(): OSMesaMakeCurrent failed for " +
                                 std::to_string(width) + "x" + std::to_string(height));
    }
}

OsmesaContext::~OsmesaContext() {
    // Release the binding first so that no thread is left with a context pointing at freed memory.
    if (OSMesaGetCurrentContext() == ctx_) OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
    OSMesaDestroyContext(ctx_);
}

void OsmesaContext::makeCurrent() {
    if (!OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, w_, h_))
        throw std::runtime_error("OsmesaContext::makeCurrent(): OSMesaMakeCurrent failed for " + std::to_string(w_) +
                                 "x" + std::to_string(h_));
}

void OsmesaContext::release() {
    // OSMesa unbinds the calling thread's context when given neither a context nor a buffer.
    if (!OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0))
        throw std::runtime_error("OsmesaContext::release(): OSMesaMakeCurrent failed to release the context");
}

void OsmesaContext::resize(int width, int height) {
    checkSize(width, height, "OsmesaContext::resize()");
    std::vector<uint8_t> buf(size_t(width) * size_t(height) * 4u, 0);
    if (!OSMesaMakeCurrent(ctx_, buf.data(), GL_UNSIGNED_BYTE, width, height))
        throw std::runtime_error("OsmesaContext::resize(): OSMesaMakeCurrent failed for " + std::to_string(width) +
                                 "x" + std::to_string(height));
    buffer_.swap(buf);
    w_ = width;
    h_ = height;
}

}  // namespace sg
