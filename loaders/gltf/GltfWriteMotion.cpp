// Skins and morph targets as glTF writes them: JOINTS_n (unsigned short) and WEIGHTS_n (float) four influences an
// attribute, a skin of the written joint nodes and their inverse bind matrices, morph targets as POSITION, NORMAL
// and TANGENT displacements with the mesh's and the node's weights. Animated Transforms go out as TRS.
#include "loaders/gltf/internal/GltfWriteMotion.h"

#include "loaders/gltf/internal/GltfDetail.h"

#include <algorithm>
#include <cmath>

namespace sg::gltf {

MotionWriter::MotionWriter(tinygltf::Model& m, std::function<int(const void*, size_t, int)> view,
                           std::vector<std::string>* warnings, const std::vector<ref_ptr<Animation>>& animations)
    : m_(m), view_(std::move(view)), warnings_(warnings), animations_(animations) {
    for (const ref_ptr<Animation>& a : animations_) {
        if (!a) continue;
        for (const AnimationChannel& c : a->channels) {
            if (!c.node) continue;
            driven_.insert(c.node.get());
            if (c.path == AnimationPath::Translation || c.path == AnimationPath::Rotation ||
                c.path == AnimationPath::Scale)
                trsDriven_.insert(c.node.get());
        }
    }
}

void MotionWriter::warn(const std::string& what) {
    if (warnings_) warnings_->push_back(what);
}

template <class T>
int MotionWriter::accessor(const std::vector<T>& v, int comp, int type, size_t count, int target) {
    tinygltf::Accessor a;
    a.bufferView = view_(v.data(), v.size() * sizeof(T), target);
    a.componentType = comp;
    a.type = type;
    a.count = count;
    m_.accessors.push_back(a);
    return int(m_.accessors.size() - 1);
}

bool MotionWriter::pinned(const Node& n) const {
    return driven_.count(&n) || (n.kind() == NodeKind::Geometry && static_cast<const Geometry&>(n).posed());
}

bool MotionWriter::trs(const Transform& t, tinygltf::Node& gn) {
    if (!trsDriven_.count(&t)) return false;
    FloatTrs f;
    if (!splitTrs(t.matrix(), f)) {
        sheared_.insert(&t);
        return false;
    }
    const dmat4& mat = t.matrix();
    if (dvec3(mat[3]) != dvec3(0.0)) gn.translation = {mat[3][0], mat[3][1], mat[3][2]};  // in double, as it is
    if (f.q != vec4(0.0f, 0.0f, 0.0f, 1.0f)) gn.rotation = {f.q.x, f.q.y, f.q.z, f.q.w};
    if (f.s != vec3(1.0f)) gn.scale = {f.s.x, f.s.y, f.s.z};
    return true;
}

void MotionWriter::written(const Node& n, int index) {
    index_.emplace(&n, index);
    if (n.kind() != NodeKind::Geometry) return;
    // Every copy of a skinned Geometry gets its mesh at the end (a shared one is written once per path).
    const auto& g = static_cast<const Geometry&>(n);
    if (g.skin() && g.mesh() && g.mesh()->primitiveCount() > 0) skinned_.emplace_back(index, &g);
}

void MotionWriter::skinAttributes(const Mesh& mesh, tinygltf::Primitive& p) {
    const size_t n = size_t(mesh.influences());
    if (n == 0) return;
    auto found = skinAttributes_.find(&mesh);
    if (found == skinAttributes_.end()) {
        std::map<std::string, int> a;
        const size_t vertices = mesh.joints().size() / n;
        for (size_t set = 0; set < n / 4; ++set) {
            std::vector<uint16_t> joints(vertices * 4);
            std::vector<float> weights(vertices * 4);
            for (size_t v = 0; v < vertices; ++v)
                for (size_t k = 0; k < 4; ++k) {
                    const size_t from = v * n + set * 4 + k;
                    weights[v * 4 + k] = mesh.weights()[from];
                    // An unused influence names joint 0: the validator asks it of zero weights.
                    joints[v * 4 + k] = mesh.weights()[from] == 0.0f ? 0 : mesh.joints()[from];
                }
            const std::string s = std::to_string(set);
            a["JOINTS_" + s] = accessor(joints, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, vertices,
                                        TINYGLTF_TARGET_ARRAY_BUFFER);
            a["WEIGHTS_" + s] = accessor(weights, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, vertices,
                                         TINYGLTF_TARGET_ARRAY_BUFFER);
        }
        found = skinAttributes_.emplace(&mesh, std::move(a)).first;
    }
    for (const auto& [name, acc] : found->second) p.attributes[name] = acc;
}

void MotionWriter::morphTargets(const Mesh& mesh, tinygltf::Primitive& p, tinygltf::Mesh& gm) {
    const std::vector<MorphTarget>& targets = mesh.morphTargets();
    if (targets.empty()) return;
    auto found = targets_.find(&mesh);
    if (found == targets_.end()) {
        const size_t n = mesh.positions().size();
        std::vector<std::map<std::string, int>> written;
        for (const MorphTarget& t : targets) {
            std::map<std::string, int> a;
            // Every target has a POSITION (glTF: one attribute at least, and bounds on it): zeros when it moves none.
            const std::vector<vec3> positions = t.positions.empty() ? std::vector<vec3>(n, vec3(0.0f)) : t.positions;
            a["POSITION"] =
                accessor(positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, TINYGLTF_TARGET_ARRAY_BUFFER);
            vec3 lo(0.0f), hi(0.0f);
            if (!positions.empty()) lo = hi = positions[0];
            for (const vec3& d : positions) {
                lo = glm::min(lo, d);
                hi = glm::max(hi, d);
            }
            m_.accessors.back().minValues = {lo.x, lo.y, lo.z};
            m_.accessors.back().maxValues = {hi.x, hi.y, hi.z};
            // A target's attribute needs the base attribute it displaces.
            if (!t.normals.empty() && !mesh.normals().empty())
                a["NORMAL"] = accessor(t.normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n,
                                       TINYGLTF_TARGET_ARRAY_BUFFER);
            if (!t.tangents.empty() && !mesh.tangents().empty())
                a["TANGENT"] = accessor(t.tangents, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n,
                                        TINYGLTF_TARGET_ARRAY_BUFFER);
            written.push_back(std::move(a));
        }
        found = targets_.emplace(&mesh, std::move(written)).first;
    }
    p.targets = found->second;
    if (!mesh.defaultWeights.empty()) {
        gm.weights.assign(mesh.defaultWeights.begin(), mesh.defaultWeights.end());
        gm.weights.resize(targets.size(), 0.0);  // glTF: one a target
    }
}

void MotionWriter::nodeWeights(const Geometry& g, tinygltf::Node& gn) {
    const std::vector<float>& w = g.morphWeights();
    const Mesh* mesh = g.mesh();
    if (w.empty() || !mesh || mesh->primitiveCount() == 0 || mesh->morphTargets().empty()) return;
    gn.weights.assign(w.begin(), w.end());
    gn.weights.resize(mesh->morphTargets().size(), 0.0);  // the rest are 0, as Geometry reads them
}

bool MotionWriter::commonRoot(const std::vector<int>& joints) const {
    std::vector<int> parent(m_.nodes.size(), -1);
    for (size_t i = 0; i < m_.nodes.size(); ++i)
        for (int c : m_.nodes[i].children) parent[size_t(c)] = int(i);
    const auto top = [&](int i) {
        while (parent[size_t(i)] >= 0) i = parent[size_t(i)];
        return i;
    };
    const int first = top(joints[0]);
    return std::all_of(joints.begin(), joints.end(), [&](int j) { return top(j) == first; });
}

int MotionWriter::skin(const Skin& s) {
    auto found = skins_.find(&s);
    if (found != skins_.end()) return found->second;
    const std::string where = "saveGltf(): skin '" + s.name + "'";
    tinygltf::Skin gs;
    gs.name = s.name;
    for (size_t k = 0; k < s.size(); ++k) {
        auto it = index_.find(s.joints()[k].get());
        if (it == index_.end()) {
            warn(where + ": joints[" + std::to_string(k) + "] ('" + s.joints()[k]->name() +
                 "') is not below the root written; the skin is left out");
            return skins_[&s] = -1;
        }
        gs.joints.push_back(it->second);
    }
    if (!commonRoot(gs.joints)) {
        warn(where + ": its joints have no common root node (glTF asks one); the skin is left out");
        return skins_[&s] = -1;
    }
    std::vector<float> ibm;
    for (const dmat4& x : s.inverseBind())
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) ibm.push_back(float(x[c][r]));  // column-major, as glTF's
    gs.inverseBindMatrices = floats(ibm, TINYGLTF_TYPE_MAT4, s.size());
    m_.skins.push_back(std::move(gs));
    return skins_[&s] = int(m_.skins.size() - 1);
}

void MotionWriter::finish(const std::function<int(const Geometry&, bool skinned)>& mesh) {
    for (const auto& [index, g] : skinned_) {
        const int s = skin(*g->skin());
        const int gm = mesh(*g, s >= 0);
        tinygltf::Node& gn = m_.nodes[size_t(index)];
        gn.mesh = gm;
        if (s >= 0) gn.skin = s;
    }
    for (size_t i = 0; i < animations_.size(); ++i)
        if (animations_[i]) animation(*animations_[i], i);
}

}  // namespace sg::gltf
