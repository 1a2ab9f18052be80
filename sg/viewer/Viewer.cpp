// Viewer's construction, its views and its settings' checks; the frame is in ViewerFrame.cpp, the pipeline in
// ViewerThreads.cpp.
#include "sg/viewer/Viewer.h"

#include "sg/gl/KeepFreedMemory.h"
#include "sg/viewer/internal/FramePacket.h"
#include "sg/viewer/internal/StageThread.h"

#include <cmath>
#include <stdexcept>

namespace sg {

namespace {
void checkRate(double rate, const char* fn) {
    if (!(rate > 0.0 && std::isfinite(rate)))
        throw std::invalid_argument(std::string(fn) + ": frameRate " + std::to_string(rate) +
                                    " is not a positive number of frames a second");
}
}  // namespace

Viewer::Viewer(Scene& scene, ViewerSettings settings)
    : scene_(&scene), own_(std::make_unique<Renderer>()), renderer_(own_.get()), settings_(std::move(settings)) {
    init();
}

Viewer::Viewer(Scene& scene, Renderer& shared, ViewerSettings settings)
    : scene_(&scene), renderer_(&shared), settings_(std::move(settings)) {
    init();
}

// What is in the threads' hands finishes (not drawn further), then the threads stop and the context comes back here
// for the renderer's destructor.
Viewer::~Viewer() {
    if (cullThread_) cullThread_->wait();
    releaseNow(dropped_);
    if (drawThread_) drawThread_->wait();
    culling_.reset();
    drawing_.reset();
    stop();
}

void Viewer::init() {
    checkRate(settings_.frameRate, "Viewer::Viewer()");
    history_ = FrameHistory(settings_.historyFrames);
    keepingFreed_ = settings_.keepFreedMemory && renderer_->softwareRasterizer();
    if (keepingFreed_) keepFreedMemory();
}

View& Viewer::addView(const Camera& camera) {
    views_.push_back(std::make_unique<View>());
    views_.back()->camera = camera;
    return *views_.back();
}

void Viewer::checkSettings() const {
    checkRate(settings_.frameRate, "Viewer::frame()");
    if (settings_.threading != ThreadingModel::SingleThreaded && !settings_.bindContext)
        throw std::invalid_argument(std::string("Viewer::frame(): the ") + threadingModelName(settings_.threading) +
                                    " threading model draws on a thread of its own and needs "
                                    "ViewerSettings::bindContext to move the GL context there");
}

void Viewer::setScene(Scene& scene) {
    if (&scene == scene_) return;
    flush();
    scene_ = &scene;
    variantsPrepared_ = false;
}

}  // namespace sg
