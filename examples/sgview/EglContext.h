// EglContext: a headless OpenGL 3.3 core context through EGL (no display, no window) that renders into a
// framebuffer object of its own. sgview's window and renderer use the system libGL, which must not meet
// OSMesa's GL in one process: this is its offscreen twin on the same libGL.
#pragma once

namespace sgview {

class EglContext {
public:
    // Makes the context current with its framebuffer bound. Throws std::runtime_error naming the EGL or GL
    // step that failed (no EGL display, no 3.3 core context, incomplete framebuffer).
    EglContext(int width, int height);
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    int width() const { return w_; }
    int height() const { return h_; }
    // Current on the calling thread, or released from it (a threaded viewer's draw thread takes it: its
    // framebuffer stays bound, being the context's). Throw std::runtime_error naming the EGL call that failed.
    void makeCurrent();
    void release();

private:
    void destroy();
    void* display_ = nullptr;  // EGLDisplay and EGLContext, kept out of this header
    void* context_ = nullptr;
    unsigned fbo_ = 0, color_ = 0, depth_ = 0;
    int w_ = 0, h_ = 0;
};

}  // namespace sgview
