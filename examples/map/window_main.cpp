// sgmap-window: the hierarchical map in a GLFW window (what `sgmap` without --headless runs). A click picks the
// region of the current level, a right click or B goes back up a level, scrolling zooms (a region covering more
// than half of the window is entered), dragging pans; E enters the region in the centre, H toggles the overlay,
// P writes a screenshot. --frames N quits after N frames (writing sgmap-window.png), --commands runs script
// commands after the first frame: both for tests without a person.
#include "map/Atlas.h"
#include "map/Options.h"
#include "map/Session.h"
#include "sg/gl/GlfwWindow.h"
#include "sg/gl/Renderer.h"

#include <GLFW/glfw3.h>

#include <cmath>
#include <cstdio>
#include <sstream>

using namespace sgmap;

namespace {

class WindowDisplay : public Display {
public:
    explicit WindowDisplay(sg::GlfwWindow& window) : window_(window) {}
    sg::Renderer& renderer() override { return renderer_; }
    void bindContext(bool current) override { current ? window_.makeCurrent() : sg::GlfwWindow::release(); }

private:
    sg::GlfwWindow& window_;
    sg::Renderer renderer_;
};

void say(const std::string& line) {
    if (!line.empty()) std::printf("%s\n", line.c_str());
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const int code = readCommandLine(argc, argv, o); code >= 0) return code;
    try {
        const std::string dir = dataDirectory(o);
        Atlas atlas(dir, atlasSettings(o));
        sg::GlfwWindow window(o.width, o.height, "sgmap");
        WindowDisplay display(window);
        Session session(atlas, display, window.width(), window.height(), o.threading);
        session.onPresent([&window] { window.swapBuffers(); });  // where the frame is drawn, after it
        bool down = false, dragged = false;
        double x = 0.0, y = 0.0;
        int shots = 0;
        window.setMouseButtonCallback([&](int button, int action, int) {
            if (button == GLFW_MOUSE_BUTTON_LEFT && action == GLFW_PRESS) down = true, dragged = false;
            if (button == GLFW_MOUSE_BUTTON_LEFT && action == GLFW_RELEASE) {
                // Window coordinates to framebuffer pixels (they differ on HiDPI screens).
                if (down && !dragged)
                    say("pick\t" + session.pickAt(x * window.width() / window.windowWidth(),
                                                  y * window.height() / window.windowHeight()));
                down = false;
            }
            if (button == GLFW_MOUSE_BUTTON_RIGHT && action == GLFW_PRESS) say("back\t" + session.back());
        });
        window.setCursorCallback([&](double nx, double ny) {
            if (down && (nx != x || ny != y)) {
                dragged = true;
                // The plane moves with the cursor: kilometres per pixel at the point looked at.
                const double perPixel = 2.0 * session.view().distance *
                                        std::tan(0.5 * session.view().fovyDegrees * M_PI / 180.0) /
                                        window.windowHeight();
                session.view().centre -= glm::dvec2(nx - x, y - ny) * perPixel;
            }
            x = nx;
            y = ny;
        });
        window.setScrollCallback([&](double, double dy) {
            session.view().distance *= std::pow(0.85, dy);
            say(session.enterByZoom());
        });
        window.setKeyCallback([&](int key, int action, int) {
            if (action != GLFW_PRESS) return;
            switch (key) {
                case GLFW_KEY_ESCAPE: window.close(); break;
                case GLFW_KEY_B: say("back\t" + session.back()); break;
                case GLFW_KEY_E: say(session.command("enter")); break;
                case GLFW_KEY_H: session.overlay = !session.overlay; break;
                case GLFW_KEY_P: say(session.command("screenshot sgmap-" + std::to_string(shots++) + ".png")); break;
                default: break;
            }
        });
        int shown = 0;
        while (!window.shouldClose() && (o.frames == 0 || shown < o.frames)) {
            window.pollEvents();
            session.view().width = window.width();
            session.view().height = window.height();
            session.frame();
            if (shown == 0 && !o.commands.empty()) {
                std::istringstream in(o.commands);
                for (std::string c; std::getline(in, c, ';');) say(session.command(c));
            }
            if (o.frames > 0 && shown + 1 == o.frames) say(session.command("screenshot sgmap-window.png"));
            ++shown;
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgmap-window: %s\n", e.what());
        return 1;
    }
}
