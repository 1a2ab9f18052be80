// AnimationPlayer: runs Animations on the app stage (the Viewer advances its player by each frame's clock step,
// ViewerSettings::animate; an application drives one of its own, or replaces the Viewer's). It writes what the
// channels drive: Transform matrices, Geometry morph weights, property setters. The update then refits only what
// moved (Scene::update()) and poses the skins whose joints moved.
#pragma once
#include "sg/core/Animation.h"
#include "sg/core/Math.h"

#include <glm/gtc/quaternion.hpp>
#include <string>
#include <unordered_map>
#include <vector>

namespace sg {

class Transform;

enum class LoopMode : uint8_t {
    Once,      // plays to the end and holds the last pose
    Repeat,    // wraps to the start
    PingPong,  // back and forth
};

class AnimationPlayer {
public:
    AnimationPlayer();
    ~AnimationPlayer();
    // Takes an animation (validated: throws std::invalid_argument as Animation::validate()); returns its index.
    // It starts stopped, at time 0, repeating, at speed 1.
    size_t add(ref_ptr<Animation> animation);
    size_t size() const;
    const Animation& animation(size_t i) const;
    // The index of the animation of that name, or of that index written in decimal; -1: none.
    int find(const std::string& nameOrIndex) const;

    // Per animation (throws std::out_of_range naming the index past the animations): play from where it is, stop
    // (back to its start, its pose no longer applied), pause (kept where it is, still applied), seek to a time in
    // seconds (applied at the next apply()), the loop mode and the speed (a time scale; negative plays backwards;
    // throws std::invalid_argument when not finite).
    void play(size_t i);
    void stop(size_t i);
    void pause(size_t i, bool paused = true);
    void seek(size_t i, double seconds);
    void setLoop(size_t i, LoopMode mode);
    void setSpeed(size_t i, double speed);
    bool playing(size_t i) const;  // playing and not paused
    double time(size_t i) const;   // its current time within [start, duration]
    // All animations: play every one, pause all (the space bar of a viewer) or resume.
    void playAll();
    void pauseAll(bool paused);
    bool allPaused() const;
    // A speed over all (multiplies each one's).
    double speed = 1.0;

    // Moves the clock of the playing animations by dt seconds (the frame's step), then applies every animation that
    // is playing or paused. Throws std::invalid_argument for a dt that is not finite.
    void advance(double dt);
    // Writes the current pose of every animation that is playing or paused; channels later in the list win over
    // earlier ones on the same target. Only what changes is written (a Transform whose matrix is the same is not
    // marked), so a still pose costs no refit.
    void apply();

private:
    struct State;
    std::vector<State> states_;
    // The rest parts (T, R, S) of each Transform some channel drives, taken when first applied.
    struct Rest {
        dvec3 t{0.0}, s{1.0};
        glm::dquat r{1.0, 0.0, 0.0, 0.0};
    };
    std::unordered_map<Transform*, Rest> rest_;
    // Each Transform the channels drive, once, with the pose apply() composes for it from its rest parts and the
    // channels (written once an apply, so that later channels win and an unchanged matrix is not set).
    struct Driven;
    std::vector<Driven> driven_;
};

}  // namespace sg
