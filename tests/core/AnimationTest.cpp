#include "sg/core/Animation.h"

#include "nodes/Geometry.h"
#include "nodes/Transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

using namespace sg;

namespace {
const double kPi = 3.14159265358979323846;

template <class F>
std::string errorOf(F f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

AnimationSampler sampler(std::vector<float> times, std::vector<float> values, uint32_t width, Interpolation i) {
    AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    s.width = width;
    s.interpolation = i;
    return s;
}

std::vector<double> at(const AnimationSampler& s, double t, bool rotation = false) {
    std::vector<double> out(s.width);
    s.sample(t, rotation, out.data());
    return out;
}

// A rotation of `degrees` about +Z as x y z w.
std::vector<double> aboutZ(double degrees) {
    const double h = degrees * kPi / 360.0;
    return {0.0, 0.0, std::sin(h), std::cos(h)};
}

void expectNear(const std::vector<double>& got, const std::vector<double>& want, double tol = 1e-6) {
    ASSERT_EQ(got.size(), want.size());
    for (size_t j = 0; j < got.size(); ++j) EXPECT_NEAR(got[j], want[j], tol) << "element " << j;
}

// A triangle with `targets` morph targets.
ref_ptr<Geometry> morphedTriangle(size_t targets) {
    auto mesh = make<Mesh>();
    mesh->set({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}, {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)}, {0, 1, 2});
    std::vector<MorphTarget> t(targets);
    for (MorphTarget& m : t) m.positions.assign(3, vec3(0, 0, 1));
    mesh->setMorphTargets(std::move(t));
    return make<Geometry>(mesh, make<Material>());
}
}  // namespace

TEST(AnimationSampler, StepHoldsEachKeyUntilTheNext) {
    const AnimationSampler s = sampler({0, 1, 2}, {10, 20, 30}, 1, Interpolation::Step);
    EXPECT_EQ(at(s, 0.0)[0], 10.0);
    EXPECT_EQ(at(s, 0.5)[0], 10.0);
    EXPECT_EQ(at(s, 0.999)[0], 10.0);
    EXPECT_EQ(at(s, 1.0)[0], 20.0);
    EXPECT_EQ(at(s, 1.9)[0], 20.0);
    EXPECT_EQ(at(s, 2.0)[0], 30.0);
}

TEST(AnimationSampler, LinearMixesTheTwoKeysAboutT) {
    const AnimationSampler s = sampler({0, 2}, {0, 0, 0, 2, 4, -6}, 3, Interpolation::Linear);
    expectNear(at(s, 1.0), {1, 2, -3}, 1e-12);
    expectNear(at(s, 0.5), {0.5, 1, -1.5}, 1e-12);
}

TEST(AnimationSampler, LinearClampsBeforeTheFirstKeyAndAfterTheLast) {
    const AnimationSampler s = sampler({1, 2}, {5, 7}, 1, Interpolation::Linear);
    EXPECT_EQ(at(s, -3.0)[0], 5.0);
    EXPECT_EQ(at(s, 1.0)[0], 5.0);
    EXPECT_EQ(at(s, 2.0)[0], 7.0);
    EXPECT_EQ(at(s, 40.0)[0], 7.0);
}

TEST(AnimationSampler, ASingleKeyIsItsValueAtAnyTime) {
    const AnimationSampler s = sampler({3}, {7, 8, 9}, 3, Interpolation::Linear);
    for (double t : {0.0, 3.0, 10.0}) expectNear(at(s, t), {7, 8, 9}, 0.0);
    // A spline's key: its value, not its tangents.
    const AnimationSampler c = sampler({3}, {1, 2, 3, 70, 80, 90, 4, 5, 6}, 3, Interpolation::CubicSpline);
    for (double t : {0.0, 3.0, 10.0}) expectNear(at(c, t), {70, 80, 90}, 0.0);
}

TEST(AnimationSampler, RotationSlerpsAtConstantAngularSpeed) {
    std::vector<float> v;
    for (double x : aboutZ(0)) v.push_back(float(x));
    for (double x : aboutZ(90)) v.push_back(float(x));
    const AnimationSampler s = sampler({0, 1}, v, 4, Interpolation::Linear);
    expectNear(at(s, 0.5, true), aboutZ(45));
    expectNear(at(s, 0.25, true), aboutZ(22.5));  // a plain mix would not be 22.5 degrees here
}

TEST(AnimationSampler, RotationTakesTheShorterArc) {
    // The second key negated is the same 90 degrees: the middle is still 45 degrees.
    std::vector<float> v;
    for (double x : aboutZ(0)) v.push_back(float(x));
    for (double x : aboutZ(90)) v.push_back(float(-x));
    const AnimationSampler s = sampler({0, 1}, v, 4, Interpolation::Linear);
    expectNear(at(s, 0.5, true), aboutZ(45));
    // 270 degrees is -90 the short way: the middle is -45 degrees, not 135.
    std::vector<float> w;
    for (double x : aboutZ(0)) w.push_back(float(x));
    for (double x : aboutZ(270)) w.push_back(float(x));
    const AnimationSampler r = sampler({0, 1}, w, 4, Interpolation::Linear);
    expectNear(at(r, 0.5, true), aboutZ(-45));
}

TEST(AnimationSampler, CubicSplineIsTheHermiteOfValuesAndTangentsTimesTheInterval) {
    // Keys at 1 and 3 (interval 2): in-tangent, value, out-tangent each.
    const AnimationSampler s = sampler({1, 3}, {0, 1, 2, -1, 4, 0}, 1, Interpolation::CubicSpline);
    const double td = 2.0, v0 = 1.0, b0 = 2.0, a1 = -1.0, v1 = 4.0;
    const auto hermite = [&](double u) {
        const double u2 = u * u, u3 = u2 * u;
        return (2 * u3 - 3 * u2 + 1) * v0 + td * (u3 - 2 * u2 + u) * b0 + (-2 * u3 + 3 * u2) * v1 + td * (u3 - u2) * a1;
    };
    EXPECT_NEAR(at(s, 2.0)[0], 3.25, 1e-12);  // by hand: 0.5 + 0.5 + 2 + 0.25
    EXPECT_NEAR(at(s, 2.0)[0], hermite(0.5), 1e-12);
    EXPECT_NEAR(at(s, 1.5)[0], hermite(0.25), 1e-12);
    EXPECT_NEAR(at(s, 2.7)[0], hermite(0.85), 1e-12);
    EXPECT_EQ(at(s, 0.0)[0], 1.0);  // clamped: the values, not the tangents
    EXPECT_EQ(at(s, 9.0)[0], 4.0);
}

TEST(AnimationSampler, CubicSplineRotationIsNormalised) {
    // Flat tangents: the middle is the mean of the two keys, which normalised is the 45 degrees between them.
    std::vector<float> v(4, 0.0f);  // in-tangent
    for (double x : aboutZ(0)) v.push_back(float(x));
    v.resize(16, 0.0f);  // out-tangent, then the next key's in-tangent
    for (double x : aboutZ(90)) v.push_back(float(x));
    v.resize(24, 0.0f);
    const AnimationSampler s = sampler({0, 1}, v, 4, Interpolation::CubicSpline);
    expectNear(at(s, 0.5, true), aboutZ(45));
}

TEST(AnimationSampler, AHintGivesTheSameValuesForwardAndBack) {
    std::vector<float> times, values;
    for (int k = 0; k < 10; ++k) times.push_back(float(k)), values.push_back(float(k * k));
    const AnimationSampler s = sampler(times, values, 1, Interpolation::Linear);
    uint32_t hint = 0;
    for (double t = -1.0; t < 11.0; t += 0.37) {
        double hinted = 0.0;
        s.sample(t, false, &hinted, &hint);
        EXPECT_DOUBLE_EQ(hinted, at(s, t)[0]) << "at " << t;
    }
    for (double t = 11.0; t > -1.0; t -= 0.61) {
        double hinted = 0.0;
        s.sample(t, false, &hinted, &hint);
        EXPECT_DOUBLE_EQ(hinted, at(s, t)[0]) << "at " << t;
    }
}

TEST(AnimationSampler, ValidateNamesWhatIsWrong) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(errorOf([] { sampler({0, 1}, {0, 1}, 1, Interpolation::Linear).validate(); }), "no error");
    EXPECT_NE(errorOf([] { sampler({}, {}, 1, Interpolation::Linear).validate(); }).find("no keys"), std::string::npos);
    EXPECT_NE(errorOf([] {
                  sampler({0, 0}, {0, 1}, 1, Interpolation::Linear).validate();
              }).find("times[1]"),
              std::string::npos);
    EXPECT_NE(errorOf([] {
                  sampler({0, 2, 1}, {0, 1, 2}, 1, Interpolation::Step).validate();
              }).find("times[2]"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  sampler({0, nan}, {0, 1}, 1, Interpolation::Linear).validate();
              }).find("times[1]"),
              std::string::npos);
    EXPECT_NE(errorOf([] {
                  sampler({0, 1}, {0, 1, 2}, 1, Interpolation::Linear).validate();
              }).find("3 values"),
              std::string::npos);
    // A spline has three groups a key.
    EXPECT_NE(errorOf([] {
                  sampler({0, 1}, {0, 1}, 1, Interpolation::CubicSpline).validate();
              }).find("2 values"),
              std::string::npos);
    EXPECT_EQ(errorOf([] {
                  sampler({0, 1}, {0, 1, 2, 3, 4, 5}, 1, Interpolation::CubicSpline).validate();
              }),
              "no error");
    EXPECT_NE(errorOf([] {
                  sampler({0, 1}, {}, 0, Interpolation::Linear).validate();
              }).find("width is 0"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  sampler({0, 1}, {0, nan}, 1, Interpolation::Linear).validate();
              }).find("values[1]"),
              std::string::npos);
}

TEST(Animation, PathNamesAreGltfs) {
    EXPECT_STREQ(pathName(AnimationPath::Translation), "translation");
    EXPECT_STREQ(pathName(AnimationPath::Rotation), "rotation");
    EXPECT_STREQ(pathName(AnimationPath::Scale), "scale");
    EXPECT_STREQ(pathName(AnimationPath::Weights), "weights");
    EXPECT_STREQ(pathName(AnimationPath::Property), "pointer");
}

TEST(Animation, DurationIsTheLastKeyOverTheSamplers) {
    Animation a;
    EXPECT_EQ(a.duration(), 0.0);
    a.samplers.push_back(sampler({0.5f, 2}, {0, 1}, 1, Interpolation::Linear));
    a.samplers.push_back(sampler({1, 3.5f}, {0, 1}, 1, Interpolation::Linear));
    EXPECT_EQ(a.duration(), 3.5);
}

TEST(Animation, ValidateChecksEachChannelAgainstWhatItDrives) {
    auto t = make<Transform>();
    Animation a;
    a.name = "walk";
    a.samplers.push_back(sampler({0, 1}, {0, 0, 0, 1, 1, 1}, 3, Interpolation::Linear));  // width 3
    a.samplers.push_back(sampler({0, 1}, {0, 1, 0, 1}, 2, Interpolation::Linear));        // width 2
    const auto channel = [](uint32_t s, AnimationPath p, ref_ptr<Node> n) {
        AnimationChannel c;
        c.sampler = s;
        c.path = p;
        c.node = std::move(n);
        return c;
    };
    const auto errorWith = [&](AnimationChannel c) {
        Animation b = a;
        b.channels = {std::move(c)};
        return errorOf([&] { b.validate(); });
    };
    EXPECT_EQ(errorWith(channel(0, AnimationPath::Translation, t)), "no error");
    EXPECT_EQ(errorWith(channel(0, AnimationPath::Scale, t)), "no error");
    EXPECT_NE(errorWith(channel(2, AnimationPath::Translation, t)).find("channels[0]: sampler 2 is past"),
              std::string::npos);
    EXPECT_NE(errorWith(channel(0, AnimationPath::Translation, nullptr)).find("no node"), std::string::npos);
    EXPECT_NE(errorWith(channel(0, AnimationPath::Translation, make<Group>())).find("not a Transform"),
              std::string::npos);
    EXPECT_NE(errorWith(channel(0, AnimationPath::Rotation, t)).find("width 3"), std::string::npos);
    // Weights: the morph target count of the Geometry, or of the first below a group.
    auto g = morphedTriangle(2);
    EXPECT_EQ(errorWith(channel(1, AnimationPath::Weights, g)), "no error");
    EXPECT_NE(errorWith(channel(0, AnimationPath::Weights, g)).find("2 morph targets"), std::string::npos);
    auto node = make<Transform>();
    node->addChild(g);
    EXPECT_EQ(errorWith(channel(1, AnimationPath::Weights, node)), "no error");
    EXPECT_NE(errorWith(channel(1, AnimationPath::Weights, make<Group>())).find("no Geometry"), std::string::npos);
    // Property: a setter.
    EXPECT_NE(errorWith(channel(1, AnimationPath::Property, nullptr)).find("no setter"), std::string::npos);
    AnimationChannel p = channel(1, AnimationPath::Property, nullptr);
    p.set = [](const double*, uint32_t) {};
    EXPECT_EQ(errorWith(p), "no error");
    // A bad sampler is named with its place.
    Animation bad = a;
    bad.samplers[1].times = {1, 0};
    EXPECT_NE(errorOf([&] { bad.validate(); }).find("'walk': samplers[1]: times[1]"), std::string::npos);
}
