// Sequence: the child its clock shows, from the children's durations, the mode, the speed and the turns.
#include "nodes/Sequence.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

namespace {
bool validDuration(double seconds) { return std::isfinite(seconds) && seconds > 0.0; }
}  // namespace

void Sequence::setDuration(size_t child, double seconds) {
    if (child >= durations_.size())
        throw std::out_of_range("Sequence::setDuration(): child " + std::to_string(child) + " of " + describe() +
                                " does not exist (" + std::to_string(durations_.size()) + " children)");
    if (!validDuration(seconds))
        throw std::invalid_argument("Sequence::setDuration(): " + describe() + ": duration " + std::to_string(seconds) +
                                    " is not a finite time above zero");
    durations_[child] = seconds;
}

double Sequence::duration(size_t child) const {
    if (child >= durations_.size())
        throw std::out_of_range("Sequence::duration(): child " + std::to_string(child) + " of " + describe() +
                                " does not exist (" + std::to_string(durations_.size()) + " children)");
    return durations_[child];
}

void Sequence::setMode(Mode m) { mode_ = m; }

void Sequence::setSpeed(double speed) {
    if (!std::isfinite(speed))
        throw std::invalid_argument("Sequence::setSpeed(): " + describe() + ": speed " + std::to_string(speed) +
                                    " is not finite");
    // Measured anew from the last advance, so that the sequence goes on from where it is at the new speed.
    if (started_ && !paused_) {
        pausedAt_ = pausedAt_ + (clock_ - start_) * speed_;
        start_ = clock_;
    }
    speed_ = speed;
}

void Sequence::setRepeats(unsigned turns) { repeats_ = turns; }

void Sequence::start(double clockTime) {
    if (!std::isfinite(clockTime))
        throw std::invalid_argument("Sequence::start(): " + describe() + ": clock time " + std::to_string(clockTime) +
                                    " is not finite");
    start_ = clock_ = clockTime;
    started_ = true;
    pausedAt_ = 0.0;
    paused_ = false;
}

void Sequence::pause(bool paused) {
    if (paused == paused_) return;
    if (paused) {
        if (started_) pausedAt_ = pausedAt_ + (clock_ - start_) * speed_;
    } else if (started_) {
        start_ = clock_;  // runs on from the time it was paused at
    }
    paused_ = paused;
}

size_t Sequence::childAt(double clockTime) const {
    const size_t n = numChildren();
    if (n == 0 || durations_.size() != n) return n;
    // The sequence's own time: where it was paused, or its time at start_ plus the clock since, scaled.
    const double own = paused_ || !started_ ? pausedAt_ : pausedAt_ + (clockTime - start_) * speed_;
    const bool swing = mode_ == Mode::Swing && n >= 3;  // with two children a swing is a loop
    double sum = 0.0;
    for (double d : durations_) sum += d;
    const double turn = swing ? 2.0 * sum - durations_.front() - durations_.back() : sum;
    if (!(turn > 0.0) || !std::isfinite(turn)) return 0;
    // After the last turn: the last child shown (running backwards, the first).
    if (repeats_ > 0 && std::abs(own) >= double(repeats_) * turn) return own > 0.0 ? (swing ? 1 : n - 1) : 0;
    double phase = own - std::floor(own / turn) * turn;
    if (!(phase >= 0.0 && phase < turn)) phase = 0.0;
    double end = 0.0;
    for (size_t k = 0; k < n; ++k)
        if (phase < (end += durations_[k])) return k;
    if (swing)
        for (size_t k = n - 2; k >= 1; --k)
            if (phase < (end += durations_[k])) return k;
    return swing ? 1 : n - 1;  // rounding at the turn's end
}

void Sequence::advance(double clockTime) {
    if (!std::isfinite(clockTime)) return;
    clock_ = clockTime;
    if (!started_) {
        start_ = clockTime;
        started_ = true;
    }
    const size_t c = childAt(clockTime);
    if (c < numChildren() && c != shown_) {
        setOnly(c);
        shown_ = c;
    }
}

void Sequence::childInserted(size_t i) {
    Switch::childInserted(i);
    durations_.insert(durations_.begin() + std::ptrdiff_t(i), validDuration(defaultDuration) ? defaultDuration : 0.1);
    shown_ = ~size_t(0);  // the indices moved: the next advance() sets the bits again
}

void Sequence::childRemoved(size_t i) {
    Switch::childRemoved(i);
    durations_.erase(durations_.begin() + std::ptrdiff_t(i));
    shown_ = ~size_t(0);
}

}  // namespace sg
