// The stage timer the viewer's parts share: milliseconds on the steady clock, since a time point or in a duration.
// Internal header: not installed (an internal/ folder); its shape may change freely.
#pragma once
#include <chrono>

namespace sg::stageclock {

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
inline double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

}  // namespace sg::stageclock
