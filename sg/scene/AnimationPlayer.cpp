// AnimationPlayer: each animation's clock (play, pause, loop modes), and its channels bound once to what they drive
// (a Transform's pose, a Geometry's weights, a setter) and written each apply() only where the value changed.
#include "sg/scene/AnimationPlayer.h"

#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "nodes/internal/MorphGeometries.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sg {

struct AnimationPlayer::Driven {
    ref_ptr<Transform> node;
    const Rest* rest = nullptr;  // in rest_, taken at the first apply that drives it
    Rest pose;
    bool touched = false;  // some applied channel drives it this apply()
};

struct AnimationPlayer::State {
    ref_ptr<Animation> animation;
    double start = 0.0, end = 0.0, time = 0.0, speed = 1.0;
    LoopMode loop = LoopMode::Repeat;
    bool playing = false;                           // play() called and not stopped since
    bool paused = false;                            // held where it is (still applied)
    bool backward = false;                          // PingPong, on its way back
    struct Bound {                                  // a channel bound to what it drives
        uint32_t driven = ~0u;                      // TRS: into driven_
        std::vector<ref_ptr<Geometry>> geometries;  // Weights
        std::vector<double> last;                   // Property: the values last written
    };
    std::vector<Bound> channels;
    std::vector<uint32_t> hints;  // per sampler: the key found last (times mostly move forward)
    std::vector<double> values;   // one channel's sampled values
};

namespace {

// The T, R, S of an affine matrix without shear (what a glTF node's TRS makes); a mirror is put in the x scale.
template <class Rest>
Rest decompose(const dmat4& m) {
    Rest r;
    r.t = dvec3(m[3]);
    const dvec3 c0(m[0]), c1(m[1]), c2(m[2]);
    r.s = dvec3(glm::length(c0), glm::length(c1), glm::length(c2));
    if (glm::determinant(glm::dmat3(m)) < 0.0) r.s.x = -r.s.x;
    if (r.s.x == 0.0 || r.s.y == 0.0 || r.s.z == 0.0) return r;  // not a Transform's (they are invertible)
    r.r = glm::normalize(glm::quat_cast(glm::dmat3(c0 / r.s.x, c1 / r.s.y, c2 / r.s.z)));
    return r;
}

// T * R * S. A scale of 0 (an object scaled away) becomes a tiny one: a Transform's matrix must be invertible.
dmat4 compose(const dvec3& t, glm::dquat r, dvec3 s) {
    const double len = glm::length(r);
    r = len > 0.0 && std::isfinite(len) ? r / len : glm::dquat(1.0, 0.0, 0.0, 0.0);
    for (int k = 0; k < 3; ++k)
        if (std::abs(s[k]) < 1e-12) s[k] = std::signbit(s[k]) ? -1e-12 : 1e-12;
    const glm::dmat3 rm = glm::mat3_cast(r);
    dmat4 m(1.0);
    for (int c = 0; c < 3; ++c) m[c] = dvec4(rm[c] * s[c], 0.0);
    m[3] = dvec4(t, 1.0);
    return m;
}

void writeWeights(Geometry& g, const double* v, uint32_t width) {
    const size_t n = std::min<size_t>(width, g.mesh() ? g.mesh()->morphTargets().size() : 0);
    const std::vector<float>& now = g.morphWeights();
    bool same = now.size() == n;
    for (size_t j = 0; same && j < n; ++j) same = now[j] == float(v[j]);
    if (same) return;
    std::vector<float> w(n);
    for (size_t j = 0; j < n; ++j) w[j] = float(v[j]);
    try {
        g.setMorphWeights(std::move(w));
    } catch (const std::invalid_argument&) {  // a spline past float's range: kept as it was
    }
}

}  // namespace

AnimationPlayer::AnimationPlayer() = default;
AnimationPlayer::~AnimationPlayer() = default;

size_t AnimationPlayer::add(ref_ptr<Animation> animation) {
    if (!animation) throw std::invalid_argument("AnimationPlayer::add(): animation is null");
    animation->validate();
    State s;
    s.start = animation->samplers.empty() ? 0.0 : animation->samplers.front().start();
    for (const AnimationSampler& sm : animation->samplers) s.start = std::min(s.start, sm.start());
    s.end = std::max(s.start, animation->duration());
    s.time = s.start;
    s.hints.assign(animation->samplers.size(), 0);
    uint32_t width = 4;  // at least a rotation's, which apply() reads
    for (const AnimationSampler& sm : animation->samplers) width = std::max(width, sm.width);
    s.values.assign(width, 0.0);
    for (const AnimationChannel& c : animation->channels) {
        State::Bound b;
        if (c.path == AnimationPath::Weights) {
            forEachMorphGeometry(*c.node, [&](Geometry& g) { b.geometries.emplace_back(&g); });
        } else if (c.path != AnimationPath::Property) {
            auto* t = static_cast<Transform*>(c.node.get());  // validate() checked the kind
            auto it = std::find_if(driven_.begin(), driven_.end(), [&](const Driven& d) { return d.node.get() == t; });
            if (it == driven_.end()) {
                driven_.emplace_back();
                driven_.back().node = t;
                it = driven_.end() - 1;
            }
            b.driven = uint32_t(it - driven_.begin());
        }
        s.channels.push_back(std::move(b));
    }
    s.animation = std::move(animation);
    states_.push_back(std::move(s));
    return states_.size() - 1;
}

size_t AnimationPlayer::size() const { return states_.size(); }

const Animation& AnimationPlayer::animation(size_t i) const {
    if (i >= states_.size())
        throw std::out_of_range("AnimationPlayer::animation(): animation " + std::to_string(i) + " of " +
                                std::to_string(states_.size()) + " does not exist");
    return *states_[i].animation;
}

int AnimationPlayer::find(const std::string& nameOrIndex) const {
    for (size_t i = 0; i < states_.size(); ++i)
        if (states_[i].animation->name == nameOrIndex) return int(i);
    if (nameOrIndex.empty() || nameOrIndex.size() > 9 ||
        !std::all_of(nameOrIndex.begin(), nameOrIndex.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return -1;
    const size_t i = std::stoul(nameOrIndex);
    return i < states_.size() ? int(i) : -1;
}

namespace {
template <class States>
auto& stateAt(States& states, size_t i, const char* fn) {
    if (i >= states.size())
        throw std::out_of_range(std::string(fn) + ": animation " + std::to_string(i) + " of " +
                                std::to_string(states.size()) + " does not exist");
    return states[i];
}
}  // namespace

void AnimationPlayer::play(size_t i) {
    State& s = stateAt(states_, i, "AnimationPlayer::play()");
    s.playing = true;
    s.paused = false;
}

void AnimationPlayer::stop(size_t i) {
    State& s = stateAt(states_, i, "AnimationPlayer::stop()");
    s.playing = s.paused = s.backward = false;
    s.time = s.start;
}

void AnimationPlayer::pause(size_t i, bool paused) { stateAt(states_, i, "AnimationPlayer::pause()").paused = paused; }

void AnimationPlayer::seek(size_t i, double seconds) {
    State& s = stateAt(states_, i, "AnimationPlayer::seek()");
    if (!std::isfinite(seconds))
        throw std::invalid_argument("AnimationPlayer::seek(): time " + std::to_string(seconds) + " is not finite");
    s.time = std::clamp(seconds, s.start, s.end);
    s.backward = false;
}

void AnimationPlayer::setLoop(size_t i, LoopMode mode) {
    stateAt(states_, i, "AnimationPlayer::setLoop()").loop = mode;
}

void AnimationPlayer::setSpeed(size_t i, double speed) {
    State& s = stateAt(states_, i, "AnimationPlayer::setSpeed()");
    if (!std::isfinite(speed))
        throw std::invalid_argument("AnimationPlayer::setSpeed(): speed " + std::to_string(speed) + " is not finite");
    s.speed = speed;
}

bool AnimationPlayer::playing(size_t i) const {
    const State& s = stateAt(states_, i, "AnimationPlayer::playing()");
    return s.playing && !s.paused;
}

double AnimationPlayer::time(size_t i) const { return stateAt(states_, i, "AnimationPlayer::time()").time; }

void AnimationPlayer::playAll() {
    for (size_t i = 0; i < states_.size(); ++i) play(i);
}

// Pauses or resumes those that play: one that is stopped stays stopped (a pause would show its first pose).
void AnimationPlayer::pauseAll(bool paused) {
    for (State& s : states_)
        if (s.playing) s.paused = paused;
}

bool AnimationPlayer::allPaused() const {
    bool any = false;
    for (const State& s : states_) {
        if (!s.playing) continue;
        if (!s.paused) return false;
        any = true;
    }
    return any;
}

namespace {
// The time `step` seconds on from `time` in [start, end], as the loop mode folds it.
double folded(double time, double step, double start, double end, LoopMode loop, bool& backward) {
    const double length = end - start;
    if (!(length > 0.0)) return start;
    if (loop == LoopMode::Once) return std::clamp(time + step, start, end);
    if (loop == LoopMode::Repeat) {
        double u = std::fmod(time - start + step, length);
        if (u < 0.0) u += length;
        return start + (u < length ? u : 0.0);
    }
    // PingPong: a phase over there and back (2 x length), forward in its first half.
    const double period = 2.0 * length;
    double u = std::fmod((backward ? period - (time - start) : time - start) + step, period);
    if (u < 0.0) u += period;
    if (!(u < period)) u = 0.0;
    backward = u > length;
    return backward ? start + period - u : start + u;
}
}  // namespace

void AnimationPlayer::advance(double dt) {
    if (!std::isfinite(dt))
        throw std::invalid_argument("AnimationPlayer::advance(): step " + std::to_string(dt) + " is not finite");
    for (State& s : states_) {
        const double step = dt * s.speed * speed;
        if (s.playing && !s.paused && step != 0.0 && std::isfinite(step))
            s.time = folded(s.time, step, s.start, s.end, s.loop, s.backward);
    }
    apply();
}

void AnimationPlayer::apply() {
    for (Driven& d : driven_) d.touched = false;
    for (State& s : states_) {
        if (!s.playing && !s.paused) continue;
        const Animation& a = *s.animation;
        for (size_t k = 0, n = std::min(a.channels.size(), s.channels.size()); k < n; ++k) {
            const AnimationChannel& c = a.channels[k];
            // What add() bound (an animation edited since keeps to what it was given then).
            if (c.sampler >= s.hints.size() || c.sampler >= a.samplers.size() ||
                a.samplers[c.sampler].width > s.values.size())
                continue;
            const AnimationSampler& sm = a.samplers[c.sampler];
            State::Bound& b = s.channels[k];
            double* v = s.values.data();
            sm.sample(s.time, c.path == AnimationPath::Rotation, v, &s.hints[c.sampler]);
            if (c.path == AnimationPath::Weights) {
                for (const ref_ptr<Geometry>& g : b.geometries) writeWeights(*g, v, sm.width);
            } else if (c.path == AnimationPath::Property) {
                if (b.last.size() == sm.width && std::equal(b.last.begin(), b.last.end(), v)) continue;
                b.last.assign(v, v + sm.width);
                c.set(v, sm.width);
            } else if (b.driven < driven_.size()) {
                Driven& d = driven_[b.driven];
                if (!d.touched) {
                    if (!d.rest) {
                        const auto [it, made] = rest_.try_emplace(d.node.get());
                        if (made) it->second = decompose<Rest>(d.node->matrix());
                        d.rest = &it->second;
                    }
                    d.pose = *d.rest;
                    d.touched = true;
                }
                if (c.path == AnimationPath::Translation) d.pose.t = dvec3(v[0], v[1], v[2]);
                if (c.path == AnimationPath::Scale) d.pose.s = dvec3(v[0], v[1], v[2]);
                if (c.path == AnimationPath::Rotation) d.pose.r = glm::dquat(v[3], v[0], v[1], v[2]);
            }
        }
    }
    for (Driven& d : driven_) {
        if (!d.touched) continue;
        const dmat4 m = compose(d.pose.t, d.pose.r, d.pose.s);
        if (m == d.node->matrix()) continue;  // a still pose: no mark, no refit
        try {
            d.node->setMatrix(m);
        } catch (const std::invalid_argument&) {  // a pose past double's range: kept as it was
        }
    }
}

}  // namespace sg
