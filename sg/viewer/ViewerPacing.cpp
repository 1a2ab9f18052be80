// Viewer's pacing: the frame-rate phases (Performer's pfPhase), the wait each one makes, and the frames' clock.
#include "sg/core/Settings.h"
#include "sg/viewer/Viewer.h"
#include "sg/viewer/internal/StageClock.h"

#include <stdexcept>
#include <thread>

namespace sg {

using stageclock::msSince;

namespace {
using Clock = stageclock::Clock;

Clock::duration toDuration(double ms) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

// Sleeps to within half a millisecond of `t` (a sleep can overrun by a tenth of one), then spins the rest: a
// frame rate held to a tenth of a millisecond, at the cost of a spin the renderer's threads never share.
void waitUntil(Clock::time_point t) {
    const auto early = t - std::chrono::microseconds(500);
    if (Clock::now() < early) std::this_thread::sleep_until(early);
    while (Clock::now() < t) {
    }
}

}  // namespace

namespace {
const EnumName<FramePhase> kFramePhases[] = {
    {FramePhase::FreeRun, "free-run"}, {FramePhase::Limit, "limit"}, {FramePhase::Lock, "lock"}};
}  // namespace

const char* framePhaseName(FramePhase p) { return enumName(kFramePhases, p); }
FramePhase parseFramePhase(const std::string& name) {
    return parseEnum(kFramePhases, name, "parseFramePhase()", "a frame phase");
}

double Viewer::now() const {
    return settings_.clock ? settings_.clock() : std::chrono::duration<double>(Clock::now() - started_).count();
}

// The phase's wait, counted only when there is one (a free run, or a frame late for its limit, waits not at all).
void Viewer::wait(Clock::time_point start, StageTimes& t) {
    const auto at = Clock::now();
    const Clock::duration period = toDuration(periodMs());
    Clock::time_point until = at;
    if (settings_.phase == FramePhase::Limit) {
        until = start + period;
    } else if (settings_.phase == FramePhase::Lock) {
        // The ticks run from the first locked frame's start; a frame waits for the first tick after its work.
        if (tick_ == Clock::time_point{} || start - tick_ > 4 * period) tick_ = start;
        until = tick_ + period;
        while (until < at) until += period;
        tick_ = until;
    }
    if (until <= at) return;
    waitUntil(until);
    t.waitMs = msSince(at);
}

}  // namespace sg
