// Viewer's failures across threads: the first stage to fail is recorded, whichever thread it ran on, and thrown on
// the application thread as a StageError once the frames in flight before it are drawn.
#include "sg/viewer/Viewer.h"

#include <algorithm>
#include <iterator>

namespace sg {

StageError::StageError(std::string stage, uint64_t frame, const std::string& what)
    : std::runtime_error("Viewer: the " + stage + " stage failed on frame " + std::to_string(frame) + ": " + what),
      stage_(std::move(stage)),
      frame_(frame) {}

void Viewer::fail(const char* stage, uint64_t frame) {
    std::lock_guard<std::mutex> lock(failMutex_);
    if (hasFailure_) return;
    failure_ = Failure{stage, frame, std::current_exception()};
    hasFailure_ = true;
}

bool Viewer::failed() {
    std::lock_guard<std::mutex> lock(failMutex_);
    return hasFailure_;
}

bool Viewer::drawFailed() {
    std::lock_guard<std::mutex> lock(failMutex_);
    static const char* const drawStages[] = {"draw", "drawn", "present", "context"};
    return hasFailure_ && std::any_of(std::begin(drawStages), std::end(drawStages),
                                      [&](const char* st) { return failure_.stage == st; });
}

// The frames in flight before the failure are drawn when they can be (not behind a failed draw), the threads stop,
// and the first failure is thrown here with its stage named.
void Viewer::rethrowFailure() {
    if (threaded_) {
        waitCull();
        waitDraw();
        stop();
    }
    releaseNow(dropped_);  // no cull runs now
    Failure f;
    {
        std::lock_guard<std::mutex> lock(failMutex_);
        f = failure_;
        failure_ = Failure{};
        hasFailure_ = false;
    }
    std::string what = "unknown exception";
    try {
        std::rethrow_exception(f.error);
    } catch (const SettingError&) {
        throw;  // an impossible setting is refused by name as it is, whichever stage met it
    } catch (const std::exception& e) {
        what = e.what();
    } catch (...) {
    }
    try {
        std::rethrow_exception(f.error);
    } catch (...) {
        throw StageError(f.stage, f.frame, what);  // nests the original
    }
}

}  // namespace sg
