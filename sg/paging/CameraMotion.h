// CameraMotion: a camera's motion over its last frames (its speed and its turn), and the camera carried ahead by
// it: where a view will probably be in a second, so that a pager can ask for that view's detail before the view
// gets there (sg::View::prefetchSeconds).
#pragma once
#include "sg/core/Camera.h"

#include <optional>

namespace sg {

class CameraMotion {
public:
    // The velocity and the turn are smoothed over about this many seconds: frame times vary from frame to frame
    // while the camera's path does not.
    static constexpr double kSmoothingSeconds = 0.2;
    // A gap longer than this between two frames (a pause, a breakpoint) starts the estimate over.
    static constexpr double kMaxGapSeconds = 1.0;
    // The predicted turn is at most this many radians: beyond it a turn carried ahead says little.
    static constexpr double kMaxTurn = 1.5707963267948966;

    // The camera as it is at `time` (seconds, increasing; FrameInfo::time). Non-finite times, and times not after
    // the last one, leave the estimate as it is.
    void observe(const Camera& camera, double time);
    // Forgets the motion (a teleport, a new path): predict() has nothing until two frames are seen again.
    void reset() { frames_ = 0; }

    // `camera` moved on by the estimated motion for `seconds` (position along the velocity, view direction turned
    // by the angular velocity), its projection and viewport unchanged; nothing before two frames were observed,
    // for seconds <= 0 or not finite, or when the camera is at rest.
    std::optional<Camera> predict(const Camera& camera, double seconds) const;

    const dvec3& velocity() const { return velocity_; }  // metres (world units) a second
    const dvec3& turn() const { return turn_; }          // the rotation vector a second (axis times radians)

private:
    int frames_ = 0;  // observed since the last reset, up to 2
    double time_ = 0.0;
    dvec3 eye_{0.0};
    glm::dmat3 toWorld_{1.0};  // the last camera's rotation from eye to world axes
    dvec3 velocity_{0.0}, turn_{0.0};
};

}  // namespace sg
