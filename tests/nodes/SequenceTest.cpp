#include "nodes/Sequence.h"

#include "nodes/Geometry.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <vector>

using namespace sg;

namespace {
// A sequence of `durations.size()` children (empty groups), each shown for its duration, started at clock 0.
ref_ptr<Sequence> sequence(const std::vector<double>& durations) {
    auto s = make<Sequence>();
    for (size_t k = 0; k < durations.size(); ++k) {
        s->addChild(make<Group>());
        s->setDuration(k, durations[k]);
    }
    s->start(0.0);
    return s;
}

// The children shown at clock times t0, t0 + step, ...
std::vector<size_t> shown(const Sequence& s, double t0, double step, int count) {
    std::vector<size_t> out;
    for (int k = 0; k < count; ++k) out.push_back(s.childAt(t0 + step * k));
    return out;
}
}  // namespace

TEST(Sequence, LoopShowsEachChildForItsDuration) {
    auto s = sequence({1, 2, 3});
    EXPECT_EQ(s->childAt(0.0), 0u);
    EXPECT_EQ(s->childAt(0.5), 0u);
    EXPECT_EQ(s->childAt(1.0), 1u);
    EXPECT_EQ(s->childAt(2.9), 1u);
    EXPECT_EQ(s->childAt(3.0), 2u);
    EXPECT_EQ(s->childAt(5.9), 2u);
    EXPECT_EQ(s->childAt(6.0), 0u);  // the next turn
    EXPECT_EQ(s->childAt(7.0), 1u);
    EXPECT_EQ(s->duration(1), 2.0);
}

TEST(Sequence, ChildrenAddedTakeTheDefaultDuration) {
    auto s = make<Sequence>();
    s->addChild(make<Group>());
    s->defaultDuration = 0.25;
    s->addChild(make<Group>());
    EXPECT_EQ(s->duration(0), 0.1);
    EXPECT_EQ(s->duration(1), 0.25);
    EXPECT_EQ(make<Sequence>()->childAt(1.0), 0u);  // no children: numChildren()
}

TEST(Sequence, SwingGoesBackAndForthShowingTheEndsOnce) {
    auto s = sequence({1, 1, 1});
    s->setMode(Sequence::Mode::Swing);
    EXPECT_EQ(shown(*s, 0.5, 1.0, 9), (std::vector<size_t>{0, 1, 2, 1, 0, 1, 2, 1, 0}));
}

TEST(Sequence, SpeedScalesTheClockAndNegativeRunsBackwards) {
    auto s = sequence({1, 1, 1});
    s->setSpeed(2.0);
    EXPECT_EQ(shown(*s, 0.25, 0.5, 6), (std::vector<size_t>{0, 1, 2, 0, 1, 2}));
    auto b = sequence({1, 1, 1});
    b->setSpeed(-1.0);
    EXPECT_EQ(shown(*b, 0.5, 1.0, 6), (std::vector<size_t>{2, 1, 0, 2, 1, 0}));
    EXPECT_THROW(b->setSpeed(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

TEST(Sequence, RepeatsThenHoldsTheLastChildShown) {
    auto s = sequence({1, 1, 1});
    s->setRepeats(2);
    EXPECT_EQ(shown(*s, 0.5, 1.0, 6), (std::vector<size_t>{0, 1, 2, 0, 1, 2}));
    EXPECT_EQ(s->childAt(6.0), 2u);
    EXPECT_EQ(s->childAt(100.0), 2u);
    // Backwards, the last child shown is the first.
    auto b = sequence({1, 1, 1});
    b->setRepeats(1);
    b->setSpeed(-1.0);
    EXPECT_EQ(shown(*b, 0.5, 1.0, 3), (std::vector<size_t>{2, 1, 0}));
    EXPECT_EQ(b->childAt(3.0), 0u);
    EXPECT_EQ(b->childAt(50.0), 0u);
}

TEST(Sequence, PauseAndSpeedZeroHoldTheCurrentChild) {
    auto s = sequence({1, 1, 1});
    s->advance(0.5);
    EXPECT_TRUE(s->isOn(0));
    EXPECT_FALSE(s->isOn(1));
    s->advance(1.5);
    EXPECT_TRUE(s->isOn(1));
    s->pause(true);
    EXPECT_TRUE(s->paused());
    s->advance(10.0);
    EXPECT_TRUE(s->isOn(1));
    s->pause(false);  // goes on from 1.5
    s->advance(10.6);
    EXPECT_TRUE(s->isOn(2));
    EXPECT_FALSE(s->isOn(1));

    auto z = sequence({1, 1, 1});
    z->advance(1.5);
    z->setSpeed(0.0);
    z->advance(100.0);
    EXPECT_TRUE(z->isOn(1));
    z->setSpeed(1.0);  // on from 1.5
    z->advance(101.0);
    EXPECT_TRUE(z->isOn(2));
}

TEST(Sequence, AdvanceMarksTheChoiceOnlyWhenItChanges) {
    auto s = sequence({1, 1, 1});
    s->advance(0.1);
    s->clearDirty();
    s->advance(0.6);  // still child 0
    EXPECT_FALSE(s->choiceChanged());
    s->advance(1.2);
    EXPECT_TRUE(s->choiceChanged());
    EXPECT_EQ(s->dirtyBits(), 0);  // a choice, not a refit
}

TEST(Sequence, BadDurationsThrow) {
    auto s = sequence({1, 1});
    EXPECT_THROW(s->setDuration(2, 1.0), std::out_of_range);
    EXPECT_THROW(s->duration(2), std::out_of_range);
    EXPECT_THROW(s->setDuration(0, 0.0), std::invalid_argument);
    EXPECT_THROW(s->setDuration(0, -1.0), std::invalid_argument);
    EXPECT_THROW(s->setDuration(0, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

TEST(Sequence, SceneUpdateTurnsItByTheFrameTime) {
    auto s = make<Sequence>();
    for (int k = 0; k < 3; ++k) {
        s->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
        s->setDuration(size_t(k), 1.0);
    }
    auto root = make<Group>();
    root->addChild(s);
    Scene scene(root);
    // Never started: it starts at the first update's time.
    const auto expectShown = [&](size_t child, const char* when) {
        const FlatImage& img = scene.image();
        ASSERT_EQ(img.kind[1], NodeKind::Switch) << when;
        for (size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(s->isOn(k), k == child) << when << ": child " << k;
            EXPECT_EQ(img.switchOn[img.aux[1] + k] != 0, k == child) << when << ": image bit " << k;
        }
    };
    scene.update(FrameInfo{0, 100.0});
    expectShown(0, "first frame");
    const uint64_t structure = scene.structureVersion();
    scene.update(FrameInfo{1, 101.5});
    expectShown(1, "1.5 s on");
    scene.update(FrameInfo{2, 102.5});
    expectShown(2, "2.5 s on");
    scene.update(FrameInfo{3, 103.2});
    expectShown(0, "the next turn");
    // The same child: no change at all.
    const uint64_t version = scene.version();
    scene.update(FrameInfo{4, 103.4});
    EXPECT_EQ(scene.version(), version);
    EXPECT_EQ(scene.structureVersion(), structure);
}
