// factory-window: the factory site in a GLFW window (what `factory` without --headless runs). Walk (the
// viewpoint collider, the eye 1.7 m over the ground, workshop walls passable, the outside switched off inside a
// workshop) or fly; the LOD choice of the walkthrough (static, time budget, stress) and the occlusion pass
// toggled by keys; a stats overlay; screenshots. --frames and --keys replay input without a person.
#include "common/MoveKeyEvents.h"
#include "common/Navigator.h"
#include "factory/KeyScript.h"
#include "factory/Site.h"
#include "factory/Walkthrough.h"
#include "sg/gl/GlfwWindow.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/TextOverlay.h"
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/PickSet.h"
#include "sg/io/ImageIO.h"
#include "sg/style/FeatureStyle.h"
#include "testbed/FactoryLighting.h"
#include "testbed/LodRun.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

using namespace factory;
using common::Navigator;
using common::NavMode;

namespace {

constexpr double kWalkSpeed = 4.0, kFlySpeed = 30.0;  // metres a second
constexpr double kScriptStep = 1.0 / 30.0;            // seconds a replayed frame moves

class FactoryWindow {
public:
    FactoryWindow(const Options& o, scenes::Factory& f, sg::Scene& scene, const scenes::PathFrame& start)
        : o_(o),
          f_(f),
          scene_(scene),
          window_(o.width, o.height, "factory"),
          nav_(scene.image().box(0), sg::dvec3(0, 0, 1)),
          collider_(colliderSettings()),
          script_(parseKeyScript(o.keys)) {
        nav_.lookAt(o.camera ? o.eye : start.eye, o.camera ? o.center : start.target);
        nav_.setMode(NavMode::Walk);
        nav_.setSpeed(kWalkSpeed);
        // Walking: each step is swept through the collider towards the ground height + 1.7 where it ends.
        nav_.setWalkMover([this](const sg::dvec3& from, const sg::dvec3& step) {
            sg::dvec3 want = from + step;
            want.z = f_.terrainHeight(want.x, want.y) + 1.7;
            return collider_.move(scene_, from, want - from);
        });
        occlusion_ = set0_.occlusion.mode;
        window_.setKeyCallback([this](int key, int action, int) { onKey(key, action); });
        window_.setMouseButtonCallback([this](int button, int action, int) {
            if (button != GLFW_MOUSE_BUTTON_LEFT) return;
            if (action == GLFW_PRESS) {
                pressX_ = x_, pressY_ = y_;
                moved_ = false;
            } else if (dragging_ && !moved_ && window_.windowWidth() > 0 && window_.windowHeight() > 0) {
                // A click (no drag): cursor positions are in window coordinates, the camera's in the framebuffer's.
                click(x_ * window_.width() / window_.windowWidth(), y_ * window_.height() / window_.windowHeight());
            }
            dragging_ = action == GLFW_PRESS;
        });
        window_.setCursorCallback([this](double x, double y) {
            if (dragging_) nav_.drag(Navigator::kLeft, x - x_, y - y_, window_.height());
            if (std::abs(x - pressX_) + std::abs(y - pressY_) > 3.0) moved_ = true;  // a click may jitter a pixel
            x_ = x;
            y_ = y;
        });
        window_.setScrollCallback([this](double, double dy) { nav_.scroll(dy); });
    }

    int run();

private:
    static sg::ViewpointSettings colliderSettings() {
        sg::ViewpointSettings s;
        s.radius = scenes::WalkPath{}.eyeRadius;  // the scripted walk's sphere
        return s;
    }
    void onKey(int key, int action);
    void press(Key k);
    bool showWorkshop();
    std::string statsText() const;
    void screenshot(const std::string& name, const sg::Image& img);
    void shootAt(uint64_t frame, std::string name);  // frame's picture to outDir/name once it is drawn
    // A click at framebuffer pixel (x, y): the feature there (a machine, a building) highlighted, its properties on
    // the overlay and printed.
    void click(double x, double y);

    const Options& o_;
    scenes::Factory& f_;
    sg::Scene& scene_;
    sg::GlfwWindow window_;
    Navigator nav_;
    sg::ViewpointCollider collider_;
    std::vector<ScriptFrame> script_;
    common::MoveKeys keys_;
    bool dragging_ = false, overlay_ = true, wantShot_ = false, moved_ = false;
    double x_ = 0.0, y_ = 0.0, pressX_ = 0.0, pressY_ = 0.0;
    sg::Camera camera_;  // the last frame's, which a click picks through
    sg::ref_ptr<sg::FeatureStyle> style_ = sg::make<sg::FeatureStyle>();  // the clicked feature's highlight
    sg::IntersectTraversal picker_;
    std::string picked_;  // the clicked feature's lines on the overlay
    double walkSpeed_ = kWalkSpeed, flySpeed_ = kFlySpeed;
    sg::LodPolicy mode_ = sg::LodPolicy::Static;
    sg::CullSettings set0_;  // the walkthrough's settings: what occlusion "on" is
    sg::OcclusionMode occlusion_;
    int workshop_ = -1;
    // The last frame, for the overlay.
    double fps_ = 0.0, frameMs_ = 0.0, cullMs_ = 0.0, drawMs_ = 0.0;
    sg::CullStats stats_;
    // Handed from the loop to the viewer's draw-side callbacks (the draw thread when threaded): the overlay's text
    // and size, and the screenshots wanted by frame number.
    std::mutex drawSide_;
    std::string overlayText_;  // empty: no overlay
    int overlayW_ = 0, overlayH_ = 0;
    std::map<uint64_t, std::string> shots_;
};

void FactoryWindow::onKey(int key, int action) {
    common::setMoveKey(keys_, key, action != GLFW_RELEASE);  // held keys
    if (action != GLFW_PRESS) return;
    switch (key) {
        case GLFW_KEY_F: press(Key::FlyWalk); break;
        case GLFW_KEY_M: press(Key::LodMode); break;
        case GLFW_KEY_O: press(Key::Occlusion); break;
        case GLFW_KEY_P:
        case GLFW_KEY_F12: press(Key::Screenshot); break;
        case GLFW_KEY_H: press(Key::Overlay); break;
        case GLFW_KEY_ESCAPE: press(Key::Quit); break;
        default: break;
    }
}

void FactoryWindow::press(Key k) {
    switch (k) {
        case Key::FlyWalk: {
            const bool walking = nav_.mode() == NavMode::Walk;
            (walking ? walkSpeed_ : flySpeed_) = nav_.speed();  // each mode keeps the speed it was left at
            nav_.setMode(walking ? NavMode::Fly : NavMode::Walk);
            nav_.setSpeed(walking ? flySpeed_ : walkSpeed_);
            std::printf("navigation: %s\n", common::navModeName(nav_.mode()));
            break;
        }
        case Key::LodMode:
            mode_ = mode_ == sg::LodPolicy::Static   ? sg::LodPolicy::Budget
                    : mode_ == sg::LodPolicy::Budget ? sg::LodPolicy::Stress
                                                     : sg::LodPolicy::Static;
            std::printf("lod: %s\n", sg::lodPolicyName(mode_));
            break;
        case Key::Occlusion:
            occlusion_ = occlusion_ == sg::OcclusionMode::Off ? set0_.occlusion.mode : sg::OcclusionMode::Off;
            std::printf("occlusion: %s\n", occlusion_ == sg::OcclusionMode::Off ? "off" : "on");
            break;
        case Key::Screenshot: wantShot_ = true; break;
        case Key::Overlay: overlay_ = !overlay_; break;
        case Key::Quit: window_.close(); break;
        default: break;
    }
    std::fflush(stdout);
}

// Inside a workshop only its interior is on; outside, the defaults (what the walkthrough does at each step).
// Returns whether it changed.
bool FactoryWindow::showWorkshop() {
    const int k = scenes::factoryWorkshopAt(f_, nav_.eye());
    if (k == workshop_) return false;
    scenes::setFactoryEye(f_, k);
    scene_.update();
    workshop_ = k;
    return true;
}

std::string FactoryWindow::statsText() const {
    char where[32] = "outside";
    if (workshop_ >= 0) std::snprintf(where, sizeof where, "inside workshop %d", workshop_);
    char fps[32] = "-";
    if (fps_ > 0.0) std::snprintf(fps, sizeof fps, "%.1f", fps_);
    char buf[640];
    std::snprintf(buf, sizeof buf,
                  "factory  [%s]  %s\n"
                  "fps %s   frame %.2f ms   cull %.2f ms   draw %.2f ms\n"
                  "triangles %llu   geometries %llu\n"
                  "LOD %s [M]   budget %.0f ms   occlusion %s [O]\n"
                  "W/A/S/D + drag move/look   F walk/fly   M LOD mode\n"
                  "O occlusion   P/F12 screenshot   H overlay   Esc quits",
                  common::navModeName(nav_.mode()), where, fps, frameMs_, cullMs_, drawMs_,
                  (unsigned long long)stats_.triangles, (unsigned long long)stats_.geometries, sg::lodPolicyName(mode_),
                  o_.budgetMs, occlusion_ == sg::OcclusionMode::Off ? "off" : "on");
    return picked_.empty() ? std::string(buf) : buf + ("\n\n" + picked_);
}

void FactoryWindow::click(double x, double y) {
    if (camera_.width() <= 0) return;  // no frame drawn yet
    sg::QueryOptions options;
    options.style = style_.get();
    const sg::PickSet::Result r = sg::PickSet().pick(picker_, scene_, camera_, x, y, options);
    style_->setHighlight(nullptr, -1, -1, sg::vec4(1.0f));
    picked_.clear();
    if (r.hit) {
        // Each feature on the hit's path, innermost first: the machine, then the workshop it stands in.
        for (const sg::FeatureAtHit& f : sg::featuresAt(r.nearest).features) {
            if (f.featureId < 0 || f.classId.empty()) continue;
            if (picked_.empty() && f.store)
                style_->setHighlight(f.store, f.propertyTable, f.featureId, {1, 0.85f, 0.1f, 1});
            picked_ += (picked_.empty() ? "picked: " : "in: ") + f.classId;
            if (!f.properties.empty()) picked_ += ", " + sg::propertiesText(f.properties);
            picked_ += "\n";
        }
        if (!picked_.empty()) picked_.pop_back();
    }
    std::printf("%s\n", picked_.empty() ? "picked: nothing" : picked_.c_str());
    std::fflush(stdout);
}

void FactoryWindow::screenshot(const std::string& name, const sg::Image& img) {
    const std::string file = (std::filesystem::path(o_.outDir) / name).string();
    try {
        sg::savePng(file, img);
        std::printf("screenshot: %s\n", file.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "factory: screenshot: %s\n", e.what());
    }
    std::fflush(stdout);
}

void FactoryWindow::shootAt(uint64_t frame, std::string name) {
    std::lock_guard<std::mutex> lock(drawSide_);
    shots_[frame] = std::move(name);
}

int FactoryWindow::run() {
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    renderer.setFeatureStyle(style_);
    sg::TextOverlay overlay;
    renderer.setLight(scenes::factoryLight(workshop_));
    // The walkthrough's LOD choice (the same frame loop as the headless run), switched by the M key.
    scenes::LodRun::Settings ls;
    ls.method = mode_;
    ls.budgetMs = o_.budgetMs;
    ls.mayDrop = false;
    ls.cull = set0_;
    ls.threading = o_.threading;
    ls.bindContext = [this](bool current) { current ? window_.makeCurrent() : sg::GlfwWindow::release(); };
    const bool threaded = o_.threading != sg::ThreadingModel::SingleThreaded;
    scenes::LodRun lod(renderer, ls);
    // After the views' draw, where the context is: the overlay, the screenshots of their frames (before the
    // swap, which leaves the back buffer undefined), the swap.
    lod.onViewer([this, &overlay, &renderer](sg::Viewer& v) {
        v.onOverlay([this, &overlay] {
            std::lock_guard<std::mutex> lock(drawSide_);
            if (!overlayText_.empty() && overlayW_ > 0)
                overlay.draw(overlayText_, overlayW_, overlayH_, overlayW_ >= 960 && overlayH_ >= 480 ? 2.0f : 1.0f);
        });
        v.onDrawn([this, &renderer](const sg::FrameInfo& fi) {
            std::string name;
            {
                std::lock_guard<std::mutex> lock(drawSide_);
                const auto it = shots_.find(fi.frame);
                if (it == shots_.end()) return;
                name = it->second;
                shots_.erase(it);
            }
            screenshot(name, renderer.readColor());
        });
        v.onPresent([this] { window_.swapBuffers(); });
    });
    int shown = 0, counted = 0, shots = 0;
    uint64_t frameNumber = 0;  // the viewer's number for the next frame (one a lod.frame())
    double last = window_.time(), since = last;
    while (!window_.shouldClose() && (!o_.framesGiven || shown < o_.frames)) {
        window_.pollEvents();
        const double now = window_.time();
        double dt = now - last;
        last = now;
        if (size_t(shown) < script_.size()) {  // replayed input moves by a fixed step: the same every run
            const ScriptFrame& s = script_[size_t(shown)];
            for (Key k : s.pressed) press(k);
            keys_.forward = s.forward;
            keys_.back = s.back;
            keys_.left = s.left;
            keys_.right = s.right;
            if (s.dragX != 0.0 || s.dragY != 0.0) nav_.drag(Navigator::kLeft, s.dragX, s.dragY, window_.height());
            if (s.click) click(s.clickX, s.clickY);
        } else if (size_t(shown) == script_.size() && !script_.empty()) {
            keys_ = common::MoveKeys{};
        }
        if (o_.framesGiven) dt = kScriptStep;
        if (window_.shouldClose()) break;
        const int w = window_.width(), h = window_.height();
        if (w <= 0 || h <= 0) {  // minimized: nothing to draw until it comes back
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            continue;
        }
        nav_.move(keys_, dt);
        scenes::PathFrame view;
        view.eye = nav_.eye();
        view.target = nav_.eye() + 10.0 * nav_.forward();
        view.walking = nav_.mode() == NavMode::Walk;
        const sg::Camera cam = scenes::pathCamera(view, w, h);
        camera_ = cam;

        lod.settings().method = mode_;
        lod.settings().limitRate = !o_.freeRun && mode_ != sg::LodPolicy::Static;  // as the headless run
        lod.settings().cull.occlusion.mode = occlusion_;
        // The light is the renderer's, read by the draw: a frame in flight must be drawn before it changes.
        if (threaded && scenes::factoryWorkshopAt(f_, nav_.eye()) != workshop_) lod.flush();
        {
            std::lock_guard<std::mutex> lock(drawSide_);
            overlayText_ = overlay_ ? statsText() : std::string();  // of the last frame drawn
            overlayW_ = w;
            overlayH_ = h;
        }
        if (wantShot_) {
            wantShot_ = false;
            char name[32];
            do std::snprintf(name, sizeof name, "factory-%04d.png", ++shots);
            while (std::filesystem::exists(std::filesystem::path(o_.outDir) / name));
            shootAt(frameNumber, name);
        }
        if (o_.framesGiven && shown + 1 == o_.frames) shootAt(frameNumber, "factory-window.png");
        const scenes::LodFrame& fr = lod.frame(scene_, cam, [&] {
            // The sun outside, the roof's light inside.
            if (showWorkshop()) renderer.setLight(scenes::factoryLight(workshop_));
        });
        ++frameNumber;
        stats_ = fr.stats;
        cullMs_ = fr.cullMs;
        drawMs_ = fr.drawMs;
        frameMs_ = fr.frameMs;
        ++shown;
        ++counted;
        if (now - since >= 0.5) {  // the rate over the last half second
            fps_ = counted / (now - since);
            counted = 0;
            since = now;
        }
    }
    stats_ = lod.flush().stats;  // the frames in flight drawn (and their screenshots written)
    const sg::dvec3 e = nav_.eye();
    std::printf("factory: %d frames; eye (%.6f, %.6f, %.6f); %s; lod %s; occlusion %s; workshop %d; triangles %llu\n",
                shown, e.x, e.y, e.z, common::navModeName(nav_.mode()), sg::lodPolicyName(mode_),
                occlusion_ == sg::OcclusionMode::Off ? "off" : "on", workshop_, (unsigned long long)stats_.triangles);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const int code = readCommandLine(argc, argv, o); code >= 0) return code;
    if (o.headless) {
        std::fprintf(stderr, "factory: --headless is the factory program's: factory-window is the window\n");
        return 2;
    }
    try {
        scenes::Factory f = buildSite(o);
        sg::Scene scene(f.root);
        scene.update();
        // The start: the scripted walk's first frame (south of its workshop, looking at it); its walls passable.
        const scenes::PathFrame start = scenes::buildWalkPath(f, scene, 10).frames.front();
        FactoryWindow window(o, f, scene, start);
        return window.run();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "factory: %s\n", e.what());
        return 1;
    }
}
