// The window: GLFW input drives the Navigator; each frame is culled and drawn through View.
#include "common/MoveKeyEvents.h"
#include "common/Navigator.h"
#include "sg/gl/GlfwWindow.h"
#include "sg/io/ImageIO.h"
#include "sgview/Modes.h"
#include "sgview/Pick.h"
#include "sgview/View.h"
#include "sgview/ViewCamera.h"

#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

namespace sgview {

using namespace sg;
using namespace common;

namespace {

class Viewer {
public:
    Viewer(const Options& o, Scene& scene, const LoadedScene& loaded)
        : o_(o),
          scene_(scene),
          window_(o.width, o.height, "sgview: " + loaded.title),
          view_(scene, loaded.title, o.threading,
                [this](bool current) { current ? window_.makeCurrent() : GlfwWindow::release(); }),
          nav_(sceneBound(scene), o.camera ? o.camera->up : loaded.up),
          start_(startCamera(o, sceneBound(scene), loaded.up)),
          walker_(walkSettings(sceneBound(scene), nav_.up())) {
        nav_.setWalkMover(collidingWalk(scene_, walker_));
        view_.setSceneLights(loaded.up, loaded.lights);
        view_.setPointShading(o.points);
        if (loaded.styleRule) view_.featureStyle().setRule(loaded.styleRule);
        view_.settings.strategy = o.strategy;
        view_.settings.occlusion.mode = o.occlusion;
        if (loaded.pageLoad) view_.enablePaging(loaded.pageLoad);
        const std::string animating = startAnimations(view_.animations(), loaded, o);
        if (!animating.empty()) std::printf("sgview: %s (space pauses)\n", animating.c_str());
        home();
        window_.setKeyCallback([this](int key, int action, int mods) { onKey(key, action, mods); });
        window_.setMouseButtonCallback([this](int button, int action, int) { onButton(button, action); });
        window_.setCursorCallback([this](double x, double y) { onCursor(x, y); });
        window_.setScrollCallback([this](double, double dy) { nav_.scroll(dy); });
        view_.onPresent([this] { window_.swapBuffers(); });  // where the frame is drawn, after it
    }

    int run();

private:
    // The start view, orbiting what it looks at: the --camera centre or the scene's.
    void home() { nav_.lookAt(start_.eye(), o_.camera ? o_.camera->center : sceneBound(scene_).center()); }
    void onKey(int key, int action, int mods);
    void onButton(int button, int action);
    void onCursor(double x, double y);
    void onPick(double x, double y);
    void screenshot(const std::string& name, const Image& img);

    const Options& o_;
    Scene& scene_;
    GlfwWindow window_;
    View view_;
    Navigator nav_;
    Camera start_;
    ViewpointCollider walker_;  // walk mode: collisions and ground following
    MoveKeys keys_;
    bool overlay_ = true, wantShot_ = false;
    int shots_ = 0;             // screenshots asked for: the next takes the first free name after them
    int held_ = -1;             // mouse button held, -1: none
    double x_ = 0.0, y_ = 0.0;  // cursor
    double pressX_ = 0.0, pressY_ = 0.0;
    bool dragged_ = false;       // moved since the press: a drag, not a click
    IntersectTraversal picker_;  // keeps its per-mesh BVHs between clicks
    std::string panel_;          // the clicked feature's properties, on the overlay
};

int Viewer::run() {
    int shown = 0;
    double last = window_.time();
    FrameStats fs;
    scene_.update();  // walking tests the scene as its last update left it (the frames' update it from then on)
    while (!window_.shouldClose() && (o_.frames == 0 || shown < o_.frames)) {
        window_.pollEvents();
        const double now = window_.time();
        const double dt = now - last;
        last = now;
        const int w = window_.width(), h = window_.height();
        if (w <= 0 || h <= 0) {  // minimized: nothing to draw until it comes back
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            continue;
        }
        nav_.move(keys_, dt);
        fs.mode = navModeName(nav_.mode());
        fs.panel = panel_;
        // The pictures are read where the frame is drawn, before its swap (after it the back buffer is undefined).
        View::Picture picture;
        if (wantShot_) {
            wantShot_ = false;
            char name[32];
            do std::snprintf(name, sizeof name, "sgview-%04d.png", ++shots_);
            while (std::filesystem::exists(name));
            picture = [this, file = std::string(name)](const Image& img) { screenshot(file, img); };
        }
        if (!o_.out.empty() && shown + 1 == o_.frames) {  // scripted runs
            View::Picture shot = std::move(picture);
            picture = [this, shot](const Image& img) {
                if (shot) shot(img);
                savePng(o_.out, img);  // a failure stops the run (the viewer rethrows it here)
            };
        }
        view_.frame(nav_.camera(w, h), overlay_, fs, std::move(picture));
        ++shown;
    }
    view_.flush();  // the frames in flight drawn, their pictures written
    std::printf("sgview: %d frames; last: %s\n", shown, view_.statsText(fs).c_str());
    return 0;
}

void Viewer::onKey(int key, int action, int) {
    setMoveKey(keys_, key, action != GLFW_RELEASE);  // held keys
    if (action != GLFW_PRESS) return;
    switch (key) {
        case GLFW_KEY_ESCAPE: window_.close(); break;
        case GLFW_KEY_1: nav_.setMode(NavMode::Trackball); break;
        case GLFW_KEY_2: nav_.setMode(NavMode::Fly); break;
        case GLFW_KEY_3: nav_.setMode(NavMode::Walk); break;
        case GLFW_KEY_C: std::printf("culling: %s\n", nextName(view_.settings.strategy)); break;
        case GLFW_KEY_O: std::printf("occlusion: %s\n", nextName(view_.settings.occlusion.mode)); break;
        case GLFW_KEY_TAB: overlay_ = !overlay_; break;
        case GLFW_KEY_HOME: home(); break;
        case GLFW_KEY_P:
        case GLFW_KEY_F12: wantShot_ = true; break;
        case GLFW_KEY_H: std::fputs(usageText(), stdout); break;
        case GLFW_KEY_SPACE: {
            sg::AnimationPlayer& p = view_.animations();
            if (p.size() == 0) break;
            p.pauseAll(!p.allPaused());
            std::printf("animations: %s\n", p.allPaused() ? "paused" : "playing");
            break;
        }
        default: break;
    }
    if (key >= GLFW_KEY_1 && key <= GLFW_KEY_3) std::printf("navigation: %s\n", navModeName(nav_.mode()));
    std::fflush(stdout);
}

void Viewer::onButton(int button, int action) {
    if (action == GLFW_PRESS && held_ < 0) {
        held_ = button;
        pressX_ = x_;
        pressY_ = y_;
        dragged_ = false;
    } else if (action == GLFW_RELEASE && button == held_) {
        held_ = -1;
        if (button == GLFW_MOUSE_BUTTON_LEFT && !dragged_) onPick(x_, y_);
    }
}

void Viewer::onCursor(double x, double y) {
    const double dx = x - x_, dy = y - y_;
    x_ = x;
    y_ = y;
    if (held_ < 0) return;
    if (std::abs(x - pressX_) + std::abs(y - pressY_) > 3.0) dragged_ = true;  // a click may jitter a pixel
    if (dragged_) nav_.drag(held_, dx, dy, window_.height());
}

void Viewer::screenshot(const std::string& name, const Image& img) {
    try {
        savePng(name, img);
        std::printf("screenshot: %s\n", name.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgview: screenshot: %s\n", e.what());
    }
    std::fflush(stdout);
}

// A left click (press and release without a drag) at window coordinates (x, y), origin top left: prints what is
// there, highlights the feature it struck (every triangle with its id) and shows its properties on the overlay.
void Viewer::onPick(double x, double y) {
    // Cursor positions are in window coordinates; the camera's viewport is the framebuffer (HiDPI differs).
    const int w = window_.width(), h = window_.height(), ww = window_.windowWidth(), wh = window_.windowHeight();
    if (w <= 0 || h <= 0 || ww <= 0 || wh <= 0) return;
    const double fx = x * w / ww, fy = y * h / wh;
    FeatureStyle& style = view_.featureStyle();
    const Pick pick = pickAt(picker_, scene_, nav_.camera(w, h), fx, fy, &style);
    std::printf("%s\n", pickReport(pick).c_str());
    std::fflush(stdout);
    style.setHighlight(nullptr, -1, -1, vec4(1.0f));
    for (const FeatureAtHit& f : pick.features.features)
        if (f.store && !f.instance && f.featureId >= 0) {
            style.setHighlight(f.store, f.propertyTable, f.featureId, vec4(1.0f, 0.85f, 0.1f, 1.0f));
            break;
        }
    panel_ = featurePanel(pick);
}

}  // namespace

int runWindow(const Options& o, Scene& scene, const LoadedScene& loaded) { return Viewer(o, scene, loaded).run(); }

}  // namespace sgview
