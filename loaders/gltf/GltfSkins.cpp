// glTF skins: a primitive's JOINTS_n and WEIGHTS_n read into its Mesh, each skin checked and made from the nodes built
// for its joints, and skinned Geometries placed beside the skeleton rather than below their node.
#include "loaders/gltf/internal/GltfConverter.h"

#include <cmath>

namespace sg::gltf {

namespace {

// Walks up from `v` through `parent`; 2 = reaches a root, 1 = on the current walk. The node a walk comes back to
// (a cycle), or -1.
int cycleAbove(int v, const std::vector<int>& parent, std::vector<uint8_t>& state) {
    std::vector<int> walk;
    while (v != -1 && state[size_t(v)] == 0) {
        state[size_t(v)] = 1;
        walk.push_back(v);
        v = parent[size_t(v)];
    }
    const int back = v != -1 && state[size_t(v)] == 1 ? v : -1;
    for (int w : walk) state[size_t(w)] = 2;
    return back;
}

}  // namespace

void checkSkins(const std::string& file, const tinygltf::Model& m) {
    const size_t n = m.nodes.size();
    std::vector<int> parent(n, -1), second(n, -1);
    for (size_t i = 0; i < n; ++i) {
        for (int c : m.nodes[i].children) {
            if (c < 0 || size_t(c) >= n || c == int(i)) continue;  // refused by the node checks
            (parent[size_t(c)] == -1 ? parent : second)[size_t(c)] = int(i);
        }
        const int s = m.nodes[i].skin;
        if (s != -1 && (s < 0 || size_t(s) >= m.skins.size()))
            fail(file, at("nodes", i) + ".skin",
                 "skin " + std::to_string(s) + " does not exist (" + std::to_string(m.skins.size()) + " skins)");
    }
    std::vector<uint8_t> state(n, 0);
    for (size_t s = 0; s < m.skins.size(); ++s) {
        const tinygltf::Skin& sk = m.skins[s];
        const std::string path = at("skins", s);
        if (sk.joints.empty()) fail(file, path + ".joints", "a skin needs at least one joint");
        for (size_t j = 0; j < sk.joints.size(); ++j) {
            const int v = sk.joints[j];
            const std::string jp = at(path + ".joints", j);
            if (v < 0 || size_t(v) >= n)
                fail(file, jp, "node " + std::to_string(v) + " does not exist (" + std::to_string(n) + " nodes)");
            if (second[size_t(v)] != -1)
                fail(file, jp,
                     "joint node " + std::to_string(v) + " has two parents, nodes[" +
                         std::to_string(parent[size_t(v)]) + "] and nodes[" + std::to_string(second[size_t(v)]) +
                         "]: a skeleton must be a tree");
            if (const int c = cycleAbove(v, parent, state); c != -1)
                fail(file, jp,
                     "joint node " + std::to_string(v) +
                         " is in or below a cycle of the node hierarchy (through nodes[" + std::to_string(c) +
                         "]): a skeleton must be a tree");
        }
        if (sk.skeleton != -1 && (sk.skeleton < 0 || size_t(sk.skeleton) >= n))
            fail(file, path + ".skeleton",
                 "node " + std::to_string(sk.skeleton) + " does not exist (" + std::to_string(n) + " nodes)");
        const int ib = sk.inverseBindMatrices;
        if (ib == -1) continue;
        const std::string ip = path + ".inverseBindMatrices";
        if (ib < 0 || size_t(ib) >= m.accessors.size())
            fail(file, ip,
                 "accessor " + std::to_string(ib) + " does not exist (" + std::to_string(m.accessors.size()) +
                     " accessors)");
        const tinygltf::Accessor& a = m.accessors[size_t(ib)];
        if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail(file, ip, "accessor " + std::to_string(ib) + " is not MAT4 of componentType 5126 (float)");
        if (a.count != sk.joints.size())
            fail(file, ip,
                 "count " + std::to_string(a.count) + " differs from the skin's " + std::to_string(sk.joints.size()) +
                     " joints");
    }
}

void Converter::skinWeights(const tinygltf::Primitive& p, Mesh& mesh, const std::string& path,
                            const std::vector<uint32_t>* order) {
    auto attr = [&](const std::string& name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    const std::string ap = path + ".attributes.";
    for (const auto& [name, acc] : p.attributes)
        if ((name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) && name.back() != '0' &&
            name.back() != '1')
            warn(ap + name, "not read: a vertex has at most 8 influences (JOINTS_0 and JOINTS_1)");
    const int influences = attr("JOINTS_1") >= 0 || attr("WEIGHTS_1") >= 0 ? 8 : 4;
    if (influences == 4 && attr("JOINTS_0") < 0 && attr("WEIGHTS_0") < 0) return;
    const size_t n = m.accessors[size_t(p.attributes.at("POSITION"))].count;
    std::vector<uint16_t> joints(n * size_t(influences));
    std::vector<float> weights(n * size_t(influences));
    for (int set = 0; set < influences / 4; ++set) {
        const std::string jn = "JOINTS_" + std::to_string(set), wn = "WEIGHTS_" + std::to_string(set);
        const int ja = attr(jn), wa = attr(wn);
        if (ja < 0 && wa < 0) bad(ap + "JOINTS_1", "needs JOINTS_0 and WEIGHTS_0 beside it");
        if (ja < 0 || wa < 0) bad(ap + (ja < 0 ? wn : jn), "needs " + (ja < 0 ? jn : wn) + " beside it");
        // validate() has checked the indices and that the counts are POSITION's.
        const tinygltf::Accessor &j = m.accessors[size_t(ja)], &w = m.accessors[size_t(wa)];
        if (j.type != TINYGLTF_TYPE_VEC4 || j.normalized ||
            (j.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
             j.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))
            bad(ap + jn,
                "accessor " + std::to_string(ja) + " is not VEC4 of unsigned bytes or shorts (not normalized)");
        const bool floats = w.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
        if (w.type != TINYGLTF_TYPE_VEC4 ||
            !(floats || (w.normalized && (w.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                          w.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))))
            bad(ap + wn,
                "accessor " + std::to_string(wa) + " is not VEC4 of floats or normalized unsigned bytes or shorts");
        const AccessorReader jr(m, j), wr(m, w);
        for (size_t v = 0; v < n; ++v)
            for (int k = 0; k < 4; ++k) {
                const size_t e = v * size_t(influences) + size_t(set * 4 + k);
                joints[e] = uint16_t(jr.component(v, k));
                weights[e] = wr.component(v, k);
                if (!std::isfinite(weights[e]) || weights[e] < 0.0f)
                    bad(ap + wn, "element " + std::to_string(v) + " has a weight that is negative or not finite (" +
                                     std::to_string(weights[e]) + ")");
            }
    }
    if (order) {  // indexed points: each vertex's influences at its index
        std::vector<uint16_t> gj;
        std::vector<float> gw;
        for (uint32_t i : *order) {
            const size_t at = size_t(i) * size_t(influences);
            gj.insert(gj.end(), joints.begin() + long(at), joints.begin() + long(at) + influences);
            gw.insert(gw.end(), weights.begin() + long(at), weights.begin() + long(at) + influences);
        }
        joints = std::move(gj);
        weights = std::move(gw);
    }
    size_t normalised = 0;
    try {
        mesh.setSkinWeights(std::move(joints), std::move(weights), influences, &normalised);
    } catch (const std::invalid_argument& e) {
        bad(ap + "WEIGHTS_0", e.what());
    }
    if (normalised)
        warn(ap + "WEIGHTS_0", "the weights of " + std::to_string(normalised) +
                                   (normalised == 1 ? " vertex do" : " vertices do") + " not sum to one: normalised");
}

void Converter::ownGeometries(int i, Group& inner, const std::string& path) {
    const tinygltf::Node& gn = m.nodes[size_t(i)];
    const auto& gs = geometries(gn.mesh);
    const std::vector<float> weights = startWeights(i);
    Skinned pending{i, ref_ptr<Group>(&inner), {}};
    for (size_t k = 0; k < gs.size(); ++k) {
        if (!gs[k]) continue;  // skipped, with a warning
        if (++ownMade > kMaxOwnGeometries)
            bad(path + ".mesh", "the file's nodes with skins or morph targets need more than " +
                                    std::to_string(kMaxOwnGeometries) + " Geometries of their own");
        auto g = make<Geometry>(ref_ptr<Mesh>(gs[k]->mesh()), ref_ptr<Material>(gs[k]->material()));
        if (!g->mesh()->morphTargets().empty()) g->setMorphWeights(weights);  // startWeights() checked the length
        nodeGeometries[i].push_back(g);
        const int material = m.meshes[size_t(gn.mesh)].primitives[k].material;
        if (material >= 0) materialUsers[material].push_back(g);  // what a material's animation pointer reaches
        if (gn.skin >= 0 && g->mesh()->influences() > 0) {
            pending.geometries.push_back({k, g});
            continue;
        }
        if (gn.skin >= 0)
            warn(at(at("meshes", size_t(gn.mesh)) + ".primitives", k),
                 "no JOINTS_0 and WEIGHTS_0 for the skin of " + path + ": drawn unskinned");
        inner.addChild(g);
    }
    if (!pending.geometries.empty()) skinned.push_back(std::move(pending));
}

ref_ptr<Skin> Converter::skin(int s) {
    if (auto it = skinsMade.find(s); it != skinsMade.end()) return it->second;
    ref_ptr<Skin>& made = skinsMade[s];
    const tinygltf::Skin& sk = m.skins[size_t(s)];  // checkSkins() has checked it
    const std::string path = at("skins", size_t(s));
    std::vector<ref_ptr<Node>> joints;
    for (size_t j = 0; j < sk.joints.size(); ++j) {
        const ref_ptr<Node>& node = nodeOf[size_t(sk.joints[j])];
        if (!node) {
            warn(at(path + ".joints", j), "node " + std::to_string(sk.joints[j]) +
                                              " was not built (outside the scene, or skipped): what the skin moves is "
                                              "drawn unskinned");
            return {};
        }
        joints.push_back(node);
    }
    std::vector<dmat4> inverseBind;
    if (sk.inverseBindMatrices >= 0) {
        const tinygltf::Accessor& a = m.accessors[size_t(sk.inverseBindMatrices)];
        const AccessorReader r(m, a);
        inverseBind.resize(a.count);
        for (size_t i = 0; i < a.count; ++i)
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 4; ++k) inverseBind[i][c][k] = r.component(i, c * 4 + k);  // column-major
    }
    try {
        made = make<Skin>(std::move(joints), std::move(inverseBind));
    } catch (const std::invalid_argument& e) {  // a matrix not finite or not affine
        bad(path + ".inverseBindMatrices", e.what());
    }
    made->name = sk.name;
    return made;
}

void Converter::skins(Group& root) {
    for (Skinned& s : skinned) {
        const tinygltf::Node& gn = m.nodes[size_t(s.node)];
        ref_ptr<Skin> sk = skin(gn.skin);
        for (auto& [k, g] : s.geometries) {
            if (!sk) {
                if (s.inner) s.inner->addChild(g);
                continue;
            }
            const Mesh& mesh = *g->mesh();
            const size_t per = size_t(mesh.influences());
            for (size_t e = 0; mesh.maxJoint() >= sk->size() && e < mesh.joints().size(); ++e)
                if (mesh.weights()[e] > 0.0f && mesh.joints()[e] >= sk->size())
                    bad(at(at("meshes", size_t(gn.mesh)) + ".primitives", k) + ".attributes.JOINTS_" +
                            std::to_string(e % per / 4),
                        "joint " + std::to_string(mesh.joints()[e]) + " of vertex " + std::to_string(e / per) +
                            " is past the " + std::to_string(sk->size()) + " joints of skins[" +
                            std::to_string(gn.skin) + "] (" + at("nodes", size_t(s.node)) + ")");
            g->setSkin(sk);  // every joint checked above: it cannot throw
            if (!s.inner) {  // an sgkit Geometry node: skinned where it is, which must not be below a joint
                for (const ref_ptr<Node>& joint : sk->joints())
                    if (g->hasAncestorOrSelf(joint.get()))
                        bad(at("nodes", size_t(s.node)) + ".skin",
                            "the sgkit Geometry is below joint '" + joint->name() + "' of its own skin");
                continue;
            }
            g->setName(gn.name);
            root.addChild(g);
        }
    }
}

}  // namespace sg::gltf
