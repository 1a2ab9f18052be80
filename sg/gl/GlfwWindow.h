// GlfwWindow: an on-screen window with an OpenGL 3.3 core context, and the input a viewer needs.
#pragma once
#include <functional>
#include <string>

struct GLFWwindow;  // from <GLFW/glfw3.h>, kept out of this header

namespace sg {

class GlfwWindow {
public:
    using KeyCallback = std::function<void(int key, int action, int mods)>;  // GLFW_KEY_*, GLFW_PRESS...
    using CursorCallback = std::function<void(double x, double y)>;          // window coordinates
    using MouseButtonCallback = std::function<void(int button, int action, int mods)>;
    using ScrollCallback = std::function<void(double dx, double dy)>;

    // Opens the window and makes its context current. Throws std::invalid_argument when w or h is
    // <= 0, and std::runtime_error with GLFW's description when GLFW or the window cannot be created.
    GlfwWindow(int w, int h, const std::string& title);
    ~GlfwWindow();
    GlfwWindow(const GlfwWindow&) = delete;
    GlfwWindow& operator=(const GlfwWindow&) = delete;

    void makeCurrent();
    // Releases the calling thread's current context (another thread may then make this one current).
    static void release();
    bool shouldClose() const;
    // Asks the window to close: shouldClose() becomes true (the window stays until destroyed).
    void close();
    void swapBuffers();
    // Buffer swaps a swap waits for (glfwSwapInterval): 0 presents at once, 1 on the display's refresh.
    void setSwapInterval(int interval);
    void pollEvents();
    // Framebuffer size in pixels (what glViewport takes; may differ from the window size on HiDPI).
    int width() const;
    int height() const;
    // Window size in screen coordinates (what cursor positions are in).
    int windowWidth() const;
    int windowHeight() const;
    // Seconds since GLFW was initialised.
    double time() const;

    void setKeyCallback(KeyCallback cb) { key_ = std::move(cb); }
    void setCursorCallback(CursorCallback cb) { cursor_ = std::move(cb); }
    void setMouseButtonCallback(MouseButtonCallback cb) { button_ = std::move(cb); }
    void setScrollCallback(ScrollCallback cb) { scroll_ = std::move(cb); }

private:
    static void onKey(GLFWwindow* w, int key, int scancode, int action, int mods);
    static void onCursor(GLFWwindow* w, double x, double y);
    static void onMouseButton(GLFWwindow* w, int button, int action, int mods);
    static void onScroll(GLFWwindow* w, double dx, double dy);

    GLFWwindow* win_ = nullptr;
    KeyCallback key_;
    CursorCallback cursor_;
    MouseButtonCallback button_;
    ScrollCallback scroll_;
};

}  // namespace sg
