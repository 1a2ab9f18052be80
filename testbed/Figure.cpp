// The test figure: its skeleton, its skin (tubes along the bones, blended across the joints) and its walk.
#include "testbed/Figure.h"

#include "sg/core/Material.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace scenes {

using namespace sg;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct JointDef {
    const char* name;
    int parent;
    dvec3 offset;  // from the parent, standing, for a 1.8 m figure
    int child;     // the joint its bone runs to, or -1: a leaf with a bone of `tip`
    dvec3 tip;
    double radius;
};

// Left is +X, the figure faces +Z.
const JointDef kJoints[kFigureJoints] = {
    {"pelvis", -1, {0, 0.95, 0}, 1, {}, 0.13},
    {"spine1", 0, {0, 0.1, 0}, 2, {}, 0.12},
    {"spine2", 1, {0, 0.12, 0}, 3, {}, 0.13},
    {"chest", 2, {0, 0.14, 0}, 4, {}, 0.15},
    {"neck", 3, {0, 0.2, 0}, 5, {}, 0.05},
    {"head", 4, {0, 0.08, 0}, -1, {0, 0.22, 0.02}, 0.1},
    {"clavicleL", 3, {0.04, 0.16, 0}, 7, {}, 0.05},
    {"upperArmL", 6, {0.15, 0, 0}, 8, {}, 0.05},
    {"forearmL", 7, {0, -0.28, 0}, 9, {}, 0.04},
    {"handL", 8, {0, -0.25, 0}, -1, {0, -0.15, 0.02}, 0.035},
    {"clavicleR", 3, {-0.04, 0.16, 0}, 11, {}, 0.05},
    {"upperArmR", 10, {-0.15, 0, 0}, 12, {}, 0.05},
    {"forearmR", 11, {0, -0.28, 0}, 13, {}, 0.04},
    {"handR", 12, {0, -0.25, 0}, -1, {0, -0.15, 0.02}, 0.035},
    {"thighL", 0, {0.09, -0.05, 0}, 15, {}, 0.07},
    {"shinL", 14, {0, -0.42, 0}, 16, {}, 0.05},
    {"footL", 15, {0, -0.42, 0}, -1, {0, -0.04, 0.18}, 0.04},
    {"thighR", 0, {-0.09, -0.05, 0}, 18, {}, 0.07},
    {"shinR", 17, {0, -0.42, 0}, 19, {}, 0.05},
    {"footR", 18, {0, -0.42, 0}, -1, {0, -0.04, 0.18}, 0.04},
};

// The figure's joints standing, in its own frame (no joint is rotated standing).
std::vector<dvec3> bindPositions(double scale) {
    std::vector<dvec3> p(kFigureJoints);
    for (int j = 0; j < kFigureJoints; ++j)
        p[size_t(j)] = (kJoints[j].parent < 0 ? dvec3(0.0) : p[size_t(kJoints[j].parent)]) + kJoints[j].offset * scale;
    return p;
}

// One vertex's joints and weights, `influences` of them, the first four then the next four.
struct Weights {
    uint16_t j[8] = {};
    float w[8] = {};
};

Weights blend(int joint, double f, int influences) {
    Weights v;
    const JointDef& d = kJoints[joint];
    double self = 1.0, parent = 0.0, child = 0.0;
    if (f < 0.3 && d.parent >= 0) {
        self = 0.5 + 0.5 * f / 0.3;
        parent = 1.0 - self;
    } else if (f > 0.7 && d.child >= 0) {
        self = 1.0 - 0.5 * (f - 0.7) / 0.3;
        child = 1.0 - self;
    }
    v.j[0] = uint16_t(joint);
    v.w[0] = float(self);
    v.j[1] = uint16_t(d.parent >= 0 ? d.parent : joint);
    v.w[1] = float(parent);
    v.j[2] = uint16_t(d.child >= 0 ? d.child : joint);
    v.w[2] = float(child);
    if (influences == 8) {  // a little of the grandparent, in the second four
        const int grand = d.parent >= 0 && kJoints[d.parent].parent >= 0 ? kJoints[d.parent].parent : joint;
        const float g = 0.05f;
        for (int k = 0; k < 3; ++k) v.w[k] *= 1.0f - g;
        v.j[4] = uint16_t(grand);
        v.w[4] = g;
    }
    return v;
}

ref_ptr<Mesh> figureMesh(const FigureOptions& opt) {
    const double scale = opt.height / 1.8;
    const std::vector<dvec3> bind = bindPositions(scale);
    std::vector<vec3> pos, nrm;
    std::vector<uint32_t> idx;
    std::vector<uint16_t> joints;
    std::vector<float> weights;
    const int k = opt.influences;
    for (int j = 0; j < kFigureJoints; ++j) {
        const JointDef& d = kJoints[j];
        const dvec3 a = bind[size_t(j)];
        const dvec3 b = d.child >= 0 ? bind[size_t(d.child)] : a + d.tip * scale;
        const dvec3 axis = glm::normalize(b - a);
        const dvec3 side = std::abs(axis.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
        const dvec3 u = glm::normalize(glm::cross(axis, side)), v = glm::cross(axis, u);
        const uint32_t base = uint32_t(pos.size());
        for (int r = 0; r <= opt.rings; ++r) {
            const double f = double(r) / opt.rings;
            const Weights w = blend(j, f, k);
            for (int s = 0; s < opt.sides; ++s) {
                const double ang = 2.0 * kPi * s / opt.sides;
                const dvec3 n = u * std::cos(ang) + v * std::sin(ang);
                pos.push_back(vec3(a + (b - a) * f + n * d.radius * scale));
                nrm.push_back(vec3(n));
                joints.insert(joints.end(), w.j, w.j + k);
                weights.insert(weights.end(), w.w, w.w + k);
            }
        }
        for (int r = 0; r < opt.rings; ++r)
            for (int s = 0; s < opt.sides; ++s) {
                const uint32_t p0 = base + uint32_t(r * opt.sides + s);
                const uint32_t p1 = base + uint32_t(r * opt.sides + (s + 1) % opt.sides);
                const uint32_t q0 = p0 + uint32_t(opt.sides), q1 = p1 + uint32_t(opt.sides);
                idx.insert(idx.end(), {p0, p1, q1, p0, q1, q0});
            }
        // Caps: a fan at each end about a centre vertex.
        for (int end = 0; end < 2; ++end) {
            const double f = end;
            const Weights w = blend(j, f, k);
            const uint32_t c = uint32_t(pos.size());
            pos.push_back(vec3(end ? b : a));
            nrm.push_back(vec3(end ? axis : -axis));
            joints.insert(joints.end(), w.j, w.j + k);
            weights.insert(weights.end(), w.w, w.w + k);
            const uint32_t ring = base + uint32_t(end * opt.rings * opt.sides);
            for (int s = 0; s < opt.sides; ++s) {
                const uint32_t p0 = ring + uint32_t(s), p1 = ring + uint32_t((s + 1) % opt.sides);
                if (end)
                    idx.insert(idx.end(), {c, p0, p1});
                else
                    idx.insert(idx.end(), {c, p1, p0});
            }
        }
    }
    auto mesh = make<Mesh>();
    mesh->set(std::move(pos), std::move(nrm), std::move(idx));
    mesh->setSkinWeights(std::move(joints), std::move(weights), k);
    return mesh;
}

// A joint's walk: its rotation (axis, angle in radians) at time t in [0, 1) of the step, and its rate.
struct Swing {
    dvec3 axis;
    std::function<double(double)> angle;
};

double d(const std::function<double(double)>& f, double t) { return (f(t + 1e-5) - f(t - 1e-5)) / 2e-5; }

Swing swingOf(int joint) {
    const double w = 2.0 * kPi;
    auto s = [w](double amp, double phase) { return [=](double t) { return amp * std::sin(w * t + phase); }; };
    const double deg = kPi / 180.0;
    switch (joint) {
        case 2: return {{0, 1, 0}, s(5 * deg, 0)};
        case 7: return {{1, 0, 0}, s(-25 * deg, 0)};
        case 11: return {{1, 0, 0}, s(25 * deg, 0)};
        case 8: return {{1, 0, 0}, [=](double t) { return -20 * deg + 10 * deg * std::sin(w * t); }};
        case 12: return {{1, 0, 0}, [=](double t) { return -20 * deg - 10 * deg * std::sin(w * t); }};
        case 14: return {{1, 0, 0}, s(30 * deg, 0)};
        case 17: return {{1, 0, 0}, s(-30 * deg, 0)};
        case 15: return {{1, 0, 0}, [=](double t) { return 25 * deg + 25 * deg * std::sin(w * t + kPi / 2); }};
        case 18: return {{1, 0, 0}, [=](double t) { return 25 * deg - 25 * deg * std::sin(w * t + kPi / 2); }};
        default: return {{0, 0, 0}, nullptr};
    }
}

ref_ptr<Animation> walkOf(const std::vector<ref_ptr<Transform>>& joints, const FigureOptions& opt, double phase) {
    auto anim = make<Animation>();
    anim->name = "walk";
    constexpr int kKeys = 9;
    std::vector<float> times;
    for (int i = 0; i < kKeys; ++i) times.push_back(float(i) / (kKeys - 1));
    for (int j = 0; j < kFigureJoints; ++j) {
        const Swing sw = swingOf(j);
        if (!sw.angle) continue;
        AnimationSampler smp;
        smp.times = times;
        smp.width = 4;
        smp.interpolation = opt.cubic ? Interpolation::CubicSpline : Interpolation::Linear;
        for (float t : times) {
            const double tt = t + phase;
            const double a = sw.angle(tt), rate = d(sw.angle, tt);
            const glm::dquat q = glm::angleAxis(a, sw.axis);
            const dvec4 dq = dvec4(sw.axis * std::cos(a / 2), -std::sin(a / 2)) * (rate / 2);  // dq/dt, x y z w
            auto push = [&](const dvec4& v) {
                for (int c = 0; c < 4; ++c) smp.values.push_back(float(v[c]));
            };
            if (opt.cubic) push(dq);
            push(dvec4(q.x, q.y, q.z, q.w));
            if (opt.cubic) push(dq);
        }
        anim->samplers.push_back(std::move(smp));
        anim->channels.push_back(
            {uint32_t(anim->samplers.size() - 1), AnimationPath::Rotation, joints[size_t(j)], {}, kJoints[j].name});
    }
    // The pelvis bobs twice a step.
    AnimationSampler bob;
    bob.width = 3;
    bob.interpolation = opt.stepBob ? Interpolation::Step : Interpolation::Linear;
    const double scale = opt.height / 1.8;
    for (float t : times) {
        bob.times.push_back(t);
        const double y = (0.95 + 0.02 * std::cos(4.0 * kPi * (t + phase))) * scale;
        bob.values.insert(bob.values.end(), {0.0f, float(y), 0.0f});
    }
    anim->samplers.push_back(std::move(bob));
    anim->channels.push_back(
        {uint32_t(anim->samplers.size() - 1), AnimationPath::Translation, joints[0], {}, kJoints[0].name});
    return anim;
}

Figure assemble(const ref_ptr<Mesh>& mesh, const ref_ptr<Material>& mat, const FigureOptions& opt, double phase) {
    const double scale = opt.height / 1.8;
    const std::vector<dvec3> bind = bindPositions(scale);
    std::vector<ref_ptr<Transform>> joints;
    std::vector<ref_ptr<Node>> skinJoints;
    std::vector<dmat4> inverseBind;
    for (int j = 0; j < kFigureJoints; ++j) {
        auto t = make<Transform>();
        t->setName(kJoints[j].name);
        t->setTranslation(kJoints[j].offset * scale);
        if (kJoints[j].parent >= 0) joints[size_t(kJoints[j].parent)]->addChild(t);
        joints.push_back(t);
        skinJoints.push_back(t);
        inverseBind.push_back(glm::translate(dmat4(1.0), -bind[size_t(j)]));
    }
    Figure f;
    f.skin = make<Skin>(std::move(skinJoints), std::move(inverseBind));
    f.skeleton = joints[0];
    f.body = make<Geometry>(mesh, mat);
    f.body->setName("body");
    f.body->setSkin(f.skin);
    f.root = make<Group>();
    f.root->setName("figure");
    f.root->addChild(f.skeleton);
    f.root->addChild(f.body);
    f.walk = walkOf(joints, opt, phase);
    return f;
}

}  // namespace

Figure makeFigure(const FigureOptions& opt) { return assemble(figureMesh(opt), make<Material>(opt.color), opt, 0.0); }

ref_ptr<Group> makeCrowd(int count, const dvec3& first, int columns, double spacing,
                         std::vector<ref_ptr<Animation>>& walks, const FigureOptions& opt, bool zUp) {
    auto crowd = make<Group>();
    crowd->setName("crowd");
    const ref_ptr<Mesh> mesh = figureMesh(opt);
    const auto mat = make<Material>(opt.color);
    columns = std::max(1, columns);
    // Y up to Z up: +90 degrees about X.
    const dmat4 up = zUp ? glm::rotate(dmat4(1.0), kPi / 2.0, dvec3(1, 0, 0)) : dmat4(1.0);
    for (int i = 0; i < count; ++i) {
        const Figure f = assemble(mesh, mat, opt, double(i) / std::max(1, count));
        const dvec3 along = zUp ? dvec3(0, 1, 0) : dvec3(0, 0, 1);
        const dvec3 at = first + dvec3((i % columns) * spacing, 0, 0) + along * ((i / columns) * spacing);
        // The skeleton's place: a Transform above the pelvis (the body, skinned, goes where the joints put it).
        auto place = make<Transform>(glm::translate(dmat4(1.0), at) * up);
        place->addChild(f.skeleton);
        auto g = make<Group>();
        g->addChild(place);
        g->addChild(f.body);
        crowd->addChild(g);
        walks.push_back(f.walk);
    }
    return crowd;
}

}  // namespace scenes
