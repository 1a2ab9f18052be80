#include "sg/scene/AnimationPlayer.h"

#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

using namespace sg;

namespace {
const double kPi = 3.14159265358979323846;

AnimationSampler linear(std::vector<float> times, std::vector<float> values, uint32_t width) {
    AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    s.width = width;
    return s;
}

AnimationChannel channel(uint32_t sampler, AnimationPath path, ref_ptr<Node> node) {
    AnimationChannel c;
    c.sampler = sampler;
    c.path = path;
    c.node = std::move(node);
    return c;
}

// x y z w of `degrees` about +Z, as floats for a sampler.
std::vector<float> aboutZ(double degrees) {
    const double h = degrees * kPi / 360.0;
    return {0.0f, 0.0f, float(std::sin(h)), float(std::cos(h))};
}

std::vector<float> concat(std::vector<float> a, const std::vector<float>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

dmat4 rotationZ(double degrees) { return glm::rotate(dmat4(1.0), degrees * kPi / 180.0, dvec3(0, 0, 1)); }

void expectMatrixNear(const dmat4& got, const dmat4& want, double tol = 1e-6) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(got[c][r], want[c][r], tol) << "column " << c << " row " << r;
}

// One translation channel on `t` from (0,0,0) at 0 s to (2,4,6) at 2 s.
ref_ptr<Animation> slide(const ref_ptr<Transform>& t, const std::string& name = "slide") {
    auto a = make<Animation>();
    a->name = name;
    a->samplers.push_back(linear({0, 2}, {0, 0, 0, 2, 4, 6}, 3));
    a->channels.push_back(channel(0, AnimationPath::Translation, t));
    return a;
}

ref_ptr<Geometry> morphedTriangle(size_t targets) {
    auto mesh = make<Mesh>();
    mesh->set({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}, {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)}, {0, 1, 2});
    std::vector<MorphTarget> t(targets);
    for (MorphTarget& m : t) m.positions.assign(3, vec3(0, 0, 1));
    mesh->setMorphTargets(std::move(t));
    return make<Geometry>(mesh, make<Material>());
}
}  // namespace

TEST(AnimationPlayer, TranslationRotationAndScaleMakeTRS) {
    auto t = make<Transform>();
    auto a = make<Animation>();
    a->samplers.push_back(linear({0, 1}, {0, 0, 0, 2, 4, 6}, 3));
    a->samplers.push_back(linear({0, 1}, concat(aboutZ(0), aboutZ(90)), 4));
    a->samplers.push_back(linear({0, 1}, {1, 1, 1, 3, 3, 3}, 3));
    a->channels.push_back(channel(0, AnimationPath::Translation, t));
    a->channels.push_back(channel(1, AnimationPath::Rotation, t));
    a->channels.push_back(channel(2, AnimationPath::Scale, t));
    AnimationPlayer p;
    const size_t i = p.add(a);
    p.play(i);
    p.advance(0.5);
    const dmat4 want =
        glm::translate(dmat4(1.0), dvec3(1, 2, 3)) * rotationZ(45.0) * glm::scale(dmat4(1.0), dvec3(2, 2, 2));
    expectMatrixNear(t->matrix(), want);
}

TEST(AnimationPlayer, PartsNoChannelDrivesKeepTheirRestValues) {
    const dmat4 rest = glm::translate(dmat4(1.0), dvec3(5, 6, 7)) * glm::scale(dmat4(1.0), dvec3(2, 2, 2));
    auto t = make<Transform>(rest);
    auto a = make<Animation>();
    a->samplers.push_back(linear({0, 1}, concat(aboutZ(0), aboutZ(90)), 4));
    a->channels.push_back(channel(0, AnimationPath::Rotation, t));
    AnimationPlayer p;
    p.add(a);
    p.play(0);
    p.seek(0, 1.0);
    p.apply();
    expectMatrixNear(t->matrix(),
                     glm::translate(dmat4(1.0), dvec3(5, 6, 7)) * rotationZ(90.0) * glm::scale(dmat4(1.0), dvec3(2)));
}

TEST(AnimationPlayer, LaterChannelsWinOnTheSameTarget) {
    auto t = make<Transform>();
    auto a = slide(t);
    a->samplers.push_back(linear({0, 2}, {1, 1, 1, 1, 1, 1}, 3));
    a->channels.push_back(channel(1, AnimationPath::Translation, t));
    AnimationPlayer p;
    p.add(a);
    p.play(0);
    p.advance(1.0);
    EXPECT_EQ(t->translation(), dvec3(1, 1, 1));
}

TEST(AnimationPlayer, PlayPauseStopSeekAndSpeedMoveTheClock) {
    auto t = make<Transform>();
    AnimationPlayer p;
    const size_t i = p.add(slide(t));
    EXPECT_FALSE(p.playing(i));
    EXPECT_EQ(p.time(i), 0.0);
    p.advance(1.0);  // stopped: the clock stays
    EXPECT_EQ(p.time(i), 0.0);
    p.play(i);
    EXPECT_TRUE(p.playing(i));
    p.advance(0.5);
    EXPECT_EQ(p.time(i), 0.5);
    EXPECT_EQ(t->translation(), dvec3(0.5, 1, 1.5));
    p.pause(i);
    EXPECT_FALSE(p.playing(i));
    p.advance(1.0);
    EXPECT_EQ(p.time(i), 0.5);
    p.pause(i, false);
    p.advance(0.25);
    EXPECT_EQ(p.time(i), 0.75);
    p.setSpeed(i, 2.0);
    p.advance(0.25);
    EXPECT_EQ(p.time(i), 1.25);
    p.speed = 2.0;  // the player's speed multiplies the animation's
    p.advance(0.125);
    EXPECT_EQ(p.time(i), 1.75);
    p.speed = 1.0;
    p.setSpeed(i, 1.0);
    p.advance(0.5);  // repeats by default: 2.25 wraps to 0.25
    EXPECT_EQ(p.time(i), 0.25);
    p.seek(i, 1.5);
    EXPECT_EQ(p.time(i), 1.5);
    p.apply();
    EXPECT_EQ(t->translation(), dvec3(1.5, 3, 4.5));
    p.seek(i, 9.0);
    EXPECT_EQ(p.time(i), 2.0);
    p.seek(i, -1.0);
    EXPECT_EQ(p.time(i), 0.0);
    p.seek(i, 1.0);
    p.stop(i);
    EXPECT_FALSE(p.playing(i));
    EXPECT_EQ(p.time(i), 0.0);
    // Backwards.
    p.play(i);
    p.setSpeed(i, -1.0);
    p.seek(i, 0.5);
    p.advance(1.0);
    EXPECT_EQ(p.time(i), 1.5);
}

TEST(AnimationPlayer, LoopModesFoldTheTime) {
    auto t = make<Transform>();
    AnimationPlayer p;
    const size_t i = p.add(slide(t));
    p.play(i);
    p.setLoop(i, LoopMode::Once);
    p.seek(i, 1.5);
    p.advance(1.0);
    EXPECT_EQ(p.time(i), 2.0);
    p.advance(1.0);
    EXPECT_EQ(p.time(i), 2.0);  // holds the last pose
    p.setSpeed(i, -1.0);
    p.seek(i, 0.5);
    p.advance(1.0);
    EXPECT_EQ(p.time(i), 0.0);

    p.setSpeed(i, 1.0);
    p.setLoop(i, LoopMode::Repeat);
    p.seek(i, 0.0);
    p.advance(4.5);
    EXPECT_EQ(p.time(i), 0.5);

    p.setLoop(i, LoopMode::PingPong);
    p.seek(i, 0.0);
    p.advance(2.5);  // to the end and 0.5 back
    EXPECT_EQ(p.time(i), 1.5);
    p.advance(1.0);
    EXPECT_EQ(p.time(i), 0.5);
    p.advance(1.0);  // to the start and 0.5 forward again
    EXPECT_EQ(p.time(i), 0.5);
    p.advance(1.0);
    EXPECT_EQ(p.time(i), 1.5);
}

TEST(AnimationPlayer, BadArgumentsThrow) {
    auto t = make<Transform>();
    AnimationPlayer p;
    EXPECT_THROW(p.add(nullptr), std::invalid_argument);
    auto bad = slide(t);
    bad->channels[0].path = AnimationPath::Rotation;  // width 3
    EXPECT_THROW(p.add(bad), std::invalid_argument);
    EXPECT_EQ(p.size(), 0u);
    p.add(slide(t));
    EXPECT_THROW(p.play(1), std::out_of_range);
    EXPECT_THROW(p.time(3), std::out_of_range);
    EXPECT_THROW(p.setSpeed(0, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    EXPECT_THROW(p.advance(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

TEST(AnimationPlayer, FindsByNameOrIndex) {
    auto t = make<Transform>();
    AnimationPlayer p;
    p.add(slide(t, "walk"));
    p.add(slide(t, "run"));
    EXPECT_EQ(p.size(), 2u);
    EXPECT_EQ(p.find("run"), 1);
    EXPECT_EQ(p.find("walk"), 0);
    EXPECT_EQ(p.find("1"), 1);
    EXPECT_EQ(p.find("2"), -1);
    EXPECT_EQ(p.find("jump"), -1);
    EXPECT_EQ(p.find(""), -1);
    EXPECT_EQ(p.animation(1).name, "run");
}

TEST(AnimationPlayer, PlayAllAndPauseAll) {
    auto t = make<Transform>(), u = make<Transform>();
    AnimationPlayer p;
    p.add(slide(t));
    p.add(slide(u));
    EXPECT_FALSE(p.allPaused());
    p.playAll();
    EXPECT_TRUE(p.playing(0) && p.playing(1));
    p.pauseAll(true);
    EXPECT_TRUE(p.allPaused());
    p.advance(1.0);
    EXPECT_EQ(p.time(0), 0.0);
    p.pauseAll(false);
    EXPECT_FALSE(p.allPaused());
    p.advance(1.0);
    EXPECT_EQ(p.time(1), 1.0);
}

TEST(AnimationPlayer, WeightsGoToEveryGeometryOfTheNode) {
    auto node = make<Transform>();
    auto g1 = morphedTriangle(2), g2 = morphedTriangle(2), deeper = morphedTriangle(2);
    node->addChild(g1);
    node->addChild(g2);
    auto child = make<Transform>();  // a child node's primitives are not this node's
    child->addChild(deeper);
    node->addChild(child);
    auto a = make<Animation>();
    a->samplers.push_back(linear({0, 1}, {0, 0, 1, 0.5f}, 2));
    a->channels.push_back(channel(0, AnimationPath::Weights, node));
    AnimationPlayer p;
    p.add(a);
    p.play(0);
    p.advance(0.5);
    EXPECT_EQ(g1->morphWeights(), (std::vector<float>{0.5f, 0.25f}));
    EXPECT_EQ(g2->morphWeights(), (std::vector<float>{0.5f, 0.25f}));
    EXPECT_TRUE(deeper->morphWeights().empty());
}

TEST(AnimationPlayer, APropertySetterReceivesTheValuesWhenTheyChange) {
    auto a = make<Animation>();
    a->samplers.push_back(linear({0, 1}, {0, 10, 20, 1, 30, 40}, 3));
    AnimationChannel c;
    c.path = AnimationPath::Property;
    c.target = "/materials/0/pbrMetallicRoughness/baseColorFactor";
    std::vector<double> got;
    int calls = 0;
    c.set = [&](const double* v, uint32_t width) {
        got.assign(v, v + width);
        calls++;
    };
    a->channels.push_back(c);
    AnimationPlayer p;
    p.add(a);
    p.play(0);
    p.advance(0.5);
    EXPECT_EQ(got, (std::vector<double>{0.5, 20, 30}));
    EXPECT_EQ(calls, 1);
    p.pause(0);
    p.advance(0.25);  // paused: the same values, not written again
    EXPECT_EQ(calls, 1);
}

TEST(AnimationPlayer, AStillPoseMarksNothing) {
    auto t = make<Transform>();
    t->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
    auto root = make<Group>();
    root->addChild(t);
    Scene scene(root);
    AnimationPlayer p;
    auto a = slide(t);
    a->samplers.push_back(linear({0, 2}, concat(aboutZ(0), aboutZ(90)), 4));
    a->channels.push_back(channel(1, AnimationPath::Rotation, t));
    p.add(a);
    p.play(0);
    p.advance(0.5);
    scene.update();
    EXPECT_EQ(t->dirtyBits(), 0);
    const uint64_t version = scene.version();
    p.apply();  // the same pose again
    EXPECT_EQ(t->dirtyBits(), 0);
    EXPECT_EQ(root->dirtyBits(), 0);
    p.pause(0);
    p.advance(0.5);  // paused: applied, unchanged
    EXPECT_EQ(t->dirtyBits(), 0);
    scene.update();
    EXPECT_EQ(scene.version(), version);
    p.pause(0, false);
    p.advance(0.5);  // moving again: marked
    EXPECT_NE(t->dirtyBits(), 0);
}
