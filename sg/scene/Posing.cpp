// Posing: a skinned or morphed Geometry's pose worked out from its nodes (the update, picks and collisions call it),
// and the mesh it makes when skinned on the CPU (the reference the renderer's skinning is compared with).
#include "sg/scene/Posing.h"

#include "nodes/Transform.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

namespace {

// Parents followed at most this deep: a graph is a tree through first parents, this only stops a broken one.
constexpr int kMaxDepth = 1 << 16;

// World matrices already worked out, by node: a skeleton's joints share most of their paths, and a skin has tens of
// joints, so a flat list searched from its newest entry (a joint's parent is most often the joint before it) is
// cheaper than a hash map.
struct Memo {
    std::vector<std::pair<const Node*, dmat4>> known;
    const dmat4* find(const Node* n) const {
        for (auto it = known.rbegin(); it != known.rend(); ++it)
            if (it->first == n) return &it->second;
        return nullptr;
    }
};

// The world matrix of `n`, reusing the products already worked out for its ancestors.
dmat4 worldOf(const Node* n, Memo& memo) {
    // The path up to the first ancestor already known (or the root), then the products down again.
    const Node* inlineUp[32];
    std::vector<const Node*> moreUp;
    size_t count = 0;
    const dmat4* known = nullptr;
    for (const Node* a = n; a && count < size_t(kMaxDepth); a = a->parent(0)) {
        if ((known = memo.find(a))) break;
        if (count < 32)
            inlineUp[count] = a;
        else
            moreUp.push_back(a);
        ++count;
    }
    dmat4 m = known ? *known : dmat4(1.0);
    for (size_t k = count; k-- > 0;) {
        const Node* a = k < 32 ? inlineUp[k] : moreUp[k - 32];
        if (a->kind() == NodeKind::Transform) m = static_cast<const Transform*>(a)->apply(m);
        memo.known.emplace_back(a, m);
    }
    return m;
}

// The mesh `src` with other positions, normals and tangents (each empty or one per position), its other arrays
// copied, without morph targets.
ref_ptr<Mesh> rebuilt(const Mesh& src, std::vector<vec3> positions, std::vector<vec3> normals,
                      std::vector<vec4> tangents) {
    ref_ptr<Mesh> out(new Mesh);
    std::vector<uint32_t> indices(src.indexCount());
    for (size_t k = 0; k < indices.size(); ++k) indices[k] = src.index(k);
    switch (src.primitive()) {
        case Primitive::Triangles:
            out->set(std::move(positions), std::move(normals), std::move(indices), src.uvs(), src.colors());
            out->setSurface(std::move(tangents), src.uvs1());
            if (!src.outline().empty()) out->setOutline(src.outline());
            break;
        case Primitive::Lines: out->setLines(std::move(positions), std::move(indices), src.colors()); break;
        case Primitive::Points: out->setPoints(std::move(positions), src.colors(), std::move(normals)); break;
    }
    if (!src.intensities().empty()) out->setIntensities(src.intensities());
    out->setPointSpacing(src.pointSpacing());
    if (src.influences() > 0 && !out->positions().empty())
        out->setSkinWeights(src.joints(), src.weights(), src.influences());
    if (src.features()) out->setFeatures(ref_ptr<const MeshFeatures>(src.features()));
    out->setSource(src.source());
    return out;
}

template <class V>
void normalise(V& v) {
    const float len = glm::length(v);
    if (len > 0.0f && std::isfinite(len)) v /= len;
}

}  // namespace

dmat4 worldMatrix(const Node& n) {
    Memo memo;
    return worldOf(&n, memo);
}

std::vector<dmat4> skinMatrices(const Skin& skin) {
    Memo memo;
    memo.known.reserve(skin.size() + 8);
    std::vector<dmat4> out(skin.size());
    for (size_t j = 0; j < skin.size(); ++j) out[j] = worldOf(skin.joints()[j].get(), memo) * skin.inverseBind()[j];
    return out;
}

ref_ptr<Mesh> morphMesh(const Mesh& mesh, const std::vector<float>& weights) {
    const std::vector<MorphTarget>& targets = mesh.morphTargets();
    const size_t n = std::min(weights.size(), targets.size());
    if (std::all_of(weights.begin(), weights.begin() + long(n), [](float w) { return w == 0.0f; })) return nullptr;
    std::vector<vec3> positions = mesh.positions(), normals = mesh.normals();
    std::vector<vec4> tangents = mesh.tangents();
    for (size_t t = 0; t < n; ++t) {
        const float w = weights[t];
        const MorphTarget& target = targets[t];
        if (w == 0.0f) continue;
        for (size_t v = 0; v < target.positions.size() && v < positions.size(); ++v)
            positions[v] += w * target.positions[v];
        for (size_t v = 0; v < target.normals.size() && v < normals.size(); ++v) normals[v] += w * target.normals[v];
        for (size_t v = 0; v < target.tangents.size() && v < tangents.size(); ++v)
            tangents[v] += vec4(w * target.tangents[v], 0.0f);
    }
    for (vec3& nv : normals) normalise(nv);
    for (vec4& tv : tangents) {
        vec3 xyz(tv);
        normalise(xyz);
        tv = vec4(xyz, tv.w);
    }
    return rebuilt(mesh, std::move(positions), std::move(normals), std::move(tangents));
}

namespace {

// The world box of a skinned pose: each joint's box of the vertices it moves, through the joint's matrix. A vertex
// goes to a weighted mean of its joints' images of it, each inside its joint's box so moved: inside their union.
Box skinnedBox(const Mesh& mesh, const std::vector<dmat4>& mats) {
    Box box;
    const std::vector<Box>& boxes = mesh.jointBoxes();
    for (size_t j = 0; j < boxes.size() && j < mats.size(); ++j)
        if (!boxes[j].empty()) box.expand(transformBox(mats[j], boxes[j]));
    return box;
}

}  // namespace

ref_ptr<const Pose> makePose(const Geometry& g, const Pose* previous) {
    ref_ptr<Pose> pose(new Pose);
    const Mesh* mesh = g.mesh();
    if (!mesh) return pose;
    pose->weights = g.morphWeights();
    pose->baseMesh = mesh->id();
    pose->baseVersion = mesh->version();
    if (previous && previous->weights == pose->weights && previous->baseMesh == pose->baseMesh &&
        previous->baseVersion == pose->baseVersion)
        pose->mesh = previous->mesh;  // the same weights on the same arrays: the same morphed mesh
    else
        pose->mesh = morphMesh(*mesh, pose->weights);
    const Mesh& drawn = pose->drawn(*mesh);
    const Skin* skin = g.skin();
    if (!skin || mesh->influences() == 0) {  // placed by its node: the box in the Geometry's frame
        pose->box = drawn.box();
        return pose;
    }
    if (mesh->maxJoint() >= skin->size())
        throw std::invalid_argument("makePose(): " + g.describe() + "'s mesh names joint " +
                                    std::to_string(mesh->maxJoint()) + ", its skin has " +
                                    std::to_string(skin->size()) + " joints");
    const std::vector<dmat4> mats = skinMatrices(*skin);
    pose->anchor = dvec3(worldMatrix(*skin->joints()[0])[3]);
    const dmat4 less = glm::translate(dmat4(1.0), -pose->anchor);
    pose->joints.resize(mats.size());
    for (size_t j = 0; j < mats.size(); ++j) toFloat(less * mats[j], pose->joints[j]);
    pose->box = skinnedBox(drawn, mats);
    return pose;
}

namespace {

// Each joint's matrix of a skinned pose back in world coordinates, in double.
std::vector<dmat4> worldJoints(const Pose& pose) {
    std::vector<dmat4> out(pose.joints.size());
    const dmat4 back = glm::translate(dmat4(1.0), pose.anchor);
    for (size_t j = 0; j < out.size(); ++j) out[j] = back * dmat4(mat4(pose.joints[j]));
    return out;
}

}  // namespace

ref_ptr<Mesh> skinMesh(const Mesh& mesh, const Pose& pose) {
    const Mesh& src = pose.drawn(mesh);
    if (!pose.skinned()) return rebuilt(src, src.positions(), src.normals(), src.tangents());
    const std::vector<dmat4> joints = worldJoints(pose);
    const size_t count = src.positions().size(), k = size_t(src.influences());
    std::vector<vec3> positions(count), normals = src.normals();
    std::vector<vec4> tangents = src.tangents();
    for (size_t v = 0; v < count; ++v) {
        // The weighted sum of the vertex's joints' matrices (joint 0 alone for a mesh without weights; a joint past
        // the pose's is left out).
        dmat4 m(0.0);
        if (k == 0) m = joints[0];
        for (size_t i = 0; i < k; ++i) {
            const float w = src.weights()[v * k + i];
            const size_t j = src.joints()[v * k + i];
            if (w > 0.0f && j < joints.size()) m += double(w) * joints[j];
        }
        positions[v] = vec3(m * dvec4(dvec3(src.positions()[v]), 1.0));
        const glm::dmat3 a(m);
        if (v < normals.size()) {
            const double det = glm::determinant(a);
            const dvec3 nv = det != 0.0 ? glm::transpose(glm::inverse(a)) * dvec3(normals[v]) : dvec3(normals[v]);
            const double len = glm::length(nv);
            normals[v] = len > 0.0 ? vec3(nv / len) : vec3(nv);
        }
        if (v < tangents.size()) {
            const dvec3 tv = a * dvec3(tangents[v]);
            const double len = glm::length(tv);
            tangents[v] = vec4(len > 0.0 ? vec3(tv / len) : vec3(tv), tangents[v].w);
        }
    }
    return rebuilt(src, std::move(positions), std::move(normals), std::move(tangents));
}

}  // namespace sg
