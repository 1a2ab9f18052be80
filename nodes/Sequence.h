// Sequence: shows its children in turn, each for its own time (Performer's pfSequence, OpenSceneGraph's
// osg::Sequence): flip-book animation, blinking lights, a machine's states. A Switch whose one child on is chosen by
// the clock: Scene::update() sets it from FrameInfo::time (the clock the Viewer's animation player runs on), so the
// image, the cull and picks see the Switch it turns and nothing else.
#pragma once
#include "nodes/Switch.h"

#include <vector>

namespace sg {

class Sequence : public Switch {
public:
    enum class Mode : uint8_t {
        Loop,   // 0 1 2 0 1 2 ...
        Swing,  // 0 1 2 1 0 1 2 ... (the ends shown once a turn)
    };
    Sequence() = default;

    // Each child's time on screen in seconds (a child added gets `defaultDuration`). Throws std::invalid_argument
    // for a time that is not finite or not above zero, std::out_of_range past the children.
    void setDuration(size_t child, double seconds);
    double duration(size_t child) const;
    double defaultDuration = 0.1;
    // The mode, the speed (time scale; 0 holds the current child; negative runs backwards), and how many turns
    // (0: for ever); after the last turn the sequence holds its last child shown. Throws std::invalid_argument for
    // a speed that is not finite.
    void setMode(Mode m);
    Mode mode() const { return mode_; }
    void setSpeed(double speed);
    double speed() const { return speed_; }
    void setRepeats(unsigned turns);
    unsigned repeats() const { return repeats_; }
    // The clock time at which the first child starts (Scene::update() measures from it); start(t) also resumes.
    // Never started: it starts at the first advance(). A pause or a speed change moves startTime() to the clock time
    // of the last advance(), the sequence's time kept.
    void start(double clockTime);
    void pause(bool paused);
    bool paused() const { return paused_; }
    double startTime() const { return start_; }

    // The child shown at clock time t (what Scene::update() turns on); numChildren() when there are none.
    size_t childAt(double clockTime) const;
    // Turns the child for clock time t on, the rest off (marks the choice only when it changed).
    void advance(double clockTime);

protected:
    void childInserted(size_t i) override;
    void childRemoved(size_t i) override;

private:
    std::vector<double> durations_;
    Mode mode_ = Mode::Loop;
    double speed_ = 1.0;
    unsigned repeats_ = 0;
    double start_ = 0.0;
    bool paused_ = false;
    double pausedAt_ = 0.0;  // the sequence's own time when paused; running, its time at start_
    double clock_ = 0.0;     // the clock time of the last advance()
    bool started_ = false;
    size_t shown_ = ~size_t(0);
};

}  // namespace sg
