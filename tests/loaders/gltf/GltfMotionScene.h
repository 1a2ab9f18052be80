// A scene in motion for the glTF writer's tests: a chain of eight joint Transforms, two Geometries skinned to it (4
// and 8 influences a vertex), a Geometry with two morph targets and weights, and an animation of the joints'
// translation (LINEAR), rotation (STEP) and scale (CUBICSPLINE) and of the morph weights (LINEAR).
#pragma once
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/core/Animation.h"

#include <string>
#include <vector>

namespace gltftest {

using namespace sg;

struct MotionScene {
    ref_ptr<Group> root;
    std::vector<ref_ptr<Transform>> joints;  // "joint0" .. "joint7": joint k at (0, k, 0), each under the one before
    ref_ptr<Geometry> skinned4, skinned8, morphed;
    ref_ptr<Animation> animation;  // "motion"
};

// Two triangles, 1 x 2, facing +Z.
inline ref_ptr<Mesh> motionQuad() {
    auto mesh = make<Mesh>();
    mesh->set({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 2, 0), vec3(1, 2, 0)}, std::vector<vec3>(4, vec3(0, 0, 1)),
              {0, 1, 2, 2, 1, 3});
    return mesh;
}

// Vertex v's joints: (k + v) % 8 for k < influences, all distinct; weights halving (sums exactly 1 in float).
inline std::vector<uint16_t> motionJoints(int influences) {
    std::vector<uint16_t> j;
    for (int v = 0; v < 4; ++v)
        for (int k = 0; k < influences; ++k) j.push_back(uint16_t((k + v) % 8));
    return j;
}
inline std::vector<float> motionWeights(int influences) {
    const std::vector<float> four = {0.5f, 0.25f, 0.125f, 0.125f};
    const std::vector<float> eight = {0.5f, 0.25f, 0.125f, 0.0625f, 0.03125f, 0.015625f, 0.0078125f, 0.0078125f};
    std::vector<float> w;
    for (int v = 0; v < 4; ++v)
        w.insert(w.end(), influences == 4 ? four.begin() : eight.begin(), influences == 4 ? four.end() : eight.end());
    return w;
}

inline std::vector<MorphTarget> motionTargets() {
    MorphTarget up, right;
    up.positions.assign(4, vec3(0.0f, 0.0f, 1.0f));
    up.normals.assign(4, vec3(0.25f, 0.0f, 0.0f));
    right.positions = {vec3(0.0f), vec3(0.5f, 0.0f, 0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(1.5f, 0.0f, 0.0f)};
    right.normals.assign(4, vec3(0.0f, 0.25f, 0.0f));
    return {up, right};
}

inline MotionScene motionScene() {
    MotionScene s;
    s.root = make<Group>();
    auto material = make<Material>(vec4(0.8f, 0.7f, 0.6f, 1.0f));
    Group* parent = s.root.get();
    std::vector<ref_ptr<Node>> joints;
    for (int k = 0; k < 8; ++k) {
        auto j = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, k == 0 ? 0 : 1, 0)));
        j->setName("joint" + std::to_string(k));
        parent->addChild(j);
        parent = j.get();
        s.joints.push_back(j);
        joints.push_back(j);
    }
    std::vector<dmat4> inverseBind;
    for (int k = 0; k < 8; ++k) inverseBind.push_back(glm::translate(dmat4(1.0), dvec3(0, -k, 0)));
    auto skin = make<Skin>(joints, inverseBind);
    skin->name = "skeleton";
    for (int influences : {4, 8}) {
        auto mesh = motionQuad();
        mesh->setSkinWeights(motionJoints(influences), motionWeights(influences), influences);
        auto g = make<Geometry>(mesh, material);
        g->setName("skinned" + std::to_string(influences));
        g->setSkin(skin);
        s.root->addChild(g);
        (influences == 4 ? s.skinned4 : s.skinned8) = g;
    }
    auto mesh = motionQuad();
    mesh->setMorphTargets(motionTargets());
    mesh->defaultWeights = {0.25f, 0.5f};
    s.morphed = make<Geometry>(mesh, material);
    s.morphed->setName("morphed");
    s.morphed->setMorphWeights({0.5f, 0.75f});
    auto holder = make<Transform>(glm::translate(dmat4(1.0), dvec3(3, 0, 0)));
    holder->setName("holder");
    holder->addChild(s.morphed);
    s.root->addChild(holder);

    s.animation = make<Animation>();
    s.animation->name = "motion";
    auto add = [&](std::vector<float> times, std::vector<float> values, uint32_t width, Interpolation i,
                   AnimationPath path, ref_ptr<Node> node) {
        AnimationSampler sampler;
        sampler.times = std::move(times);
        sampler.values = std::move(values);
        sampler.width = width;
        sampler.interpolation = i;
        s.animation->samplers.push_back(std::move(sampler));
        AnimationChannel c;
        c.sampler = uint32_t(s.animation->samplers.size() - 1);
        c.path = path;
        c.node = std::move(node);
        c.target = c.node->name();
        s.animation->channels.push_back(std::move(c));
    };
    add({0, 1, 2}, {0, 1, 0, 1, 1, 0, 1, 3, 0}, 3, Interpolation::Linear, AnimationPath::Translation, s.joints[1]);
    add({0, 0.5f, 1.5f}, {0, 0, 0, 1, 0, 0, 0.6f, 0.8f, 0, 1, 0, 0}, 4, Interpolation::Step, AnimationPath::Rotation,
        s.joints[2]);
    // Per key: in-tangent, value, out-tangent.
    add({0, 1}, {0, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 2, 2, 2, 0, 0, 0}, 3, Interpolation::CubicSpline,
        AnimationPath::Scale, s.joints[3]);
    add({0, 1}, {0, 0, 1, 0.5f}, 2, Interpolation::Linear, AnimationPath::Weights, s.morphed);
    return s;
}

}  // namespace gltftest
