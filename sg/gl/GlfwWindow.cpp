#include "sg/gl/GlfwWindow.h"

#include <GLFW/glfw3.h>

#include <stdexcept>
#include <string>

namespace sg {

namespace {

int g_windows = 0;  // GLFW is initialised while any window exists

std::string glfwErrorText() {
    const char* desc = nullptr;
    const int code = glfwGetError(&desc);
    if (code == GLFW_NO_ERROR) return "unknown GLFW error";
    return std::string(desc ? desc : "GLFW error") + " (GLFW error " + std::to_string(code) + ")";
}

GlfwWindow* self(GLFWwindow* w) { return static_cast<GlfwWindow*>(glfwGetWindowUserPointer(w)); }

}  // namespace

GlfwWindow::GlfwWindow(int w, int h, const std::string& title) {
    if (w <= 0 || h <= 0)
        throw std::invalid_argument("GlfwWindow::GlfwWindow(): size " + std::to_string(w) + "x" + std::to_string(h) +
                                    " has no area");
    if (g_windows == 0 && glfwInit() != GLFW_TRUE)
        throw std::runtime_error("GlfwWindow::GlfwWindow(): glfwInit failed: " + glfwErrorText());
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    win_ = glfwCreateWindow(w, h, title.c_str(), nullptr, nullptr);
    if (!win_) {
        const std::string err = glfwErrorText();
        if (g_windows == 0) glfwTerminate();
        throw std::runtime_error("GlfwWindow::GlfwWindow(): cannot create a " + std::to_string(w) + "x" +
                                 std::to_string(h) + " window with an OpenGL 3.3 core context: " + err);
    }
    ++g_windows;
    glfwSetWindowUserPointer(win_, this);
    glfwSetKeyCallback(win_, &GlfwWindow::onKey);
    glfwSetCursorPosCallback(win_, &GlfwWindow::onCursor);
    glfwSetMouseButtonCallback(win_, &GlfwWindow::onMouseButton);
    glfwSetScrollCallback(win_, &GlfwWindow::onScroll);
    glfwMakeContextCurrent(win_);
}

GlfwWindow::~GlfwWindow() {
    glfwDestroyWindow(win_);
    if (--g_windows == 0) glfwTerminate();
}

void GlfwWindow::makeCurrent() { glfwMakeContextCurrent(win_); }
void GlfwWindow::release() { glfwMakeContextCurrent(nullptr); }
bool GlfwWindow::shouldClose() const { return glfwWindowShouldClose(win_) == GLFW_TRUE; }
void GlfwWindow::close() { glfwSetWindowShouldClose(win_, GLFW_TRUE); }
void GlfwWindow::swapBuffers() { glfwSwapBuffers(win_); }

void GlfwWindow::setSwapInterval(int interval) {
    glfwMakeContextCurrent(win_);
    glfwSwapInterval(interval);
}
void GlfwWindow::pollEvents() { glfwPollEvents(); }
double GlfwWindow::time() const { return glfwGetTime(); }

int GlfwWindow::width() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(win_, &w, &h);
    return w;
}

int GlfwWindow::height() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(win_, &w, &h);
    return h;
}

int GlfwWindow::windowWidth() const {
    int w = 0, h = 0;
    glfwGetWindowSize(win_, &w, &h);
    return w;
}

int GlfwWindow::windowHeight() const {
    int w = 0, h = 0;
    glfwGetWindowSize(win_, &w, &h);
    return h;
}

void GlfwWindow::onKey(GLFWwindow* w, int key, int, int action, int mods) {
    if (auto* s = self(w); s && s->key_) s->key_(key, action, mods);
}
void GlfwWindow::onCursor(GLFWwindow* w, double x, double y) {
    if (auto* s = self(w); s && s->cursor_) s->cursor_(x, y);
}
void GlfwWindow::onMouseButton(GLFWwindow* w, int button, int action, int mods) {
    if (auto* s = self(w); s && s->button_) s->button_(button, action, mods);
}
void GlfwWindow::onScroll(GLFWwindow* w, double dx, double dy) {
    if (auto* s = self(w); s && s->scroll_) s->scroll_(dx, dy);
}

}  // namespace sg
