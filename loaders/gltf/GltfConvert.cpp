// A validated tinygltf model to an sgkit graph: the default scene's node tree walked from its roots, each node
// built as a Transform (or one of sgkit's own kinds from `extras`) with its mesh, camera and light. Materials,
// meshes, node kinds, instancing and cameras are converted in files of their own (internal/GltfConverter.h).
#include "loaders/gltf/internal/GltfConverter.h"

#include "nodes/Instance.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>

namespace sg::gltf {

dmat4 Converter::localMatrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        dmat4 r;
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) r[c][k] = n.matrix[size_t(c * 4 + k)];
        return r;
    }
    dmat4 r(1.0);
    if (n.translation.size() == 3) r = glm::translate(r, dvec3(n.translation[0], n.translation[1], n.translation[2]));
    if (n.rotation.size() == 4) {
        const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF: x y z w
        const double len = glm::length(q);
        if (len > 0.0) r = r * glm::mat4_cast(q / len);
    }
    if (n.scale.size() == 3) r = glm::scale(r, dvec3(n.scale[0], n.scale[1], n.scale[2]));
    return r;
}

ref_ptr<Node> Converter::build(int i, const dmat4& parentWorld) {
    const tinygltf::Node& gn = m.nodes[size_t(i)];
    const std::string path = at("nodes", size_t(i));
    ++nodesDone;
    const Value* sx = sgkitExtras(gn.extras);
    const std::string xp = path + ".extras." + kExtrasKey;
    const dmat4 local = localMatrix(gn);
    const dmat4 world = parentWorld * local;
    checkWorld(gn, path, world);
    if (gn.camera >= 0) camera(gn.camera, world, gn.name);
    if (const int light = nodeLight(m, gn, path, world, out.lights, out.warnings); light >= 0)
        lightEntries[light].push_back(out.lights.size() - 1);
    const long long id = nodeId(sx, xp);
    if (id >= 0) {
        auto it = byId.find(id);
        if (it != byId.end()) return it->second;
    }
    const std::string kind = nodeKind(gn, sx, xp);
    // An instanced sgkit LOD (saveGltf's): a Transform holds the instances, each of the LOD over the mesh.
    const bool instancedLod = kind == "LOD" && instancing(gn) && gn.mesh >= 0;
    ref_ptr<LOD> lodPrototype;
    ref_ptr<Node> node = makeNode(kind, sx, xp, gn, local, path, instancedLod, lodPrototype);
    if (!node) return {};
    Node* inner =
        node->kind() == NodeKind::Transform && kind != "Transform" && !instancedLod ? node->child(0) : node.get();
    label(*inner, gn, sx, xp);
    addMesh(i, kind, sx, xp, inner, world, path, instancedLod, lodPrototype);
    if (instancedLod && !gn.children.empty())
        bad(path + ".children", "an instanced sgkit LOD has no children: its mesh is its one level");
    if (!instancedLod) children(gn, kind, sx, xp, inner, world, path);
    countExpanded(node.get(), inner, kind, path);
    if (id >= 0) byId[id] = node;
    if (size_t(i) < nodeOf.size() && !nodeOf[size_t(i)]) nodeOf[size_t(i)] = node;
    return node;
}

void Converter::checkWorld(const tinygltf::Node& gn, const std::string& path, const dmat4& world) {
    const std::string overflow = nonFiniteElement(world);
    if (overflow.empty()) return;
    const char* field = gn.matrix.size()        ? ".matrix"
                        : gn.scale.size()       ? ".scale"
                        : gn.translation.size() ? ".translation"
                                                : "";
    bad(path + field, "world matrix is not finite (" + overflow + ")");
}

long long Converter::nodeId(const Value* sx, const std::string& xp) {
    if (!sx || !sx->Has("id")) return -1;
    const double v = number(*sx, "id", xp, -1);
    if (v < 0 || v > 9007199254740992.0 || v != std::floor(v)) bad(xp + ".id", "must be a non-negative integer");
    return (long long)v;
}

std::string Converter::nodeKind(const tinygltf::Node& gn, const Value* sx, const std::string& xp) {
    std::string kind = sx ? string(*sx, "kind", xp, "Transform") : "Transform";
    // Packers move a mesh to a node of its own (gltfpack: a child with KHR_mesh_quantization's dequantizing
    // transform), leaving an sgkit Geometry without it: read as a Transform over what it became.
    if (kind == "Geometry" && gn.mesh < 0 && !gn.children.empty()) kind = "Transform";
    return kind;
}

ref_ptr<Node> Converter::makeNode(const std::string& kind, const Value* sx, const std::string& xp,
                                  const tinygltf::Node& gn, const dmat4& local, const std::string& path,
                                  bool instancedLod, ref_ptr<LOD>& lodPrototype) {
    ref_ptr<Node> node;
    try {
        node = makeKind(kind, sx, xp, gn, local, path);
        if (instancedLod) {
            lodPrototype = ref_ptr<LOD>(static_cast<LOD*>(node.get()));
            node = makeKind("Transform", nullptr, xp, gn, local, path);
        }
    } catch (const std::invalid_argument& e) {
        if (kind == "Transform") {  // e.g. a zero scale (animations use it to hide things)
            warn(path, std::string("matrix cannot be used (") + e.what() + "), node skipped");
            return {};
        }
        bad(xp, e.what());
    }
    if (kind != "Transform" && kind != "Instance" && !instancedLod && local != dmat4(1.0)) {
        // sgkit writes its kinds without a matrix; one given by hand places the node in a Transform.
        auto t = make<Transform>();
        try {
            t->setMatrix(local);
        } catch (const std::invalid_argument& e) {  // singular, as a plain Transform's above
            warn(path, std::string("matrix cannot be used (") + e.what() + "), node skipped");
            return {};
        }
        t->addChild(node);
        node = t;  // the extras below still apply to the inner node: keep a handle on it
    }
    return node;
}

void Converter::label(Node& inner, const tinygltf::Node& gn, const Value* sx, const std::string& xp) {
    if (!gn.name.empty()) inner.setName(gn.name);
    if (GltfProperties p = properties(gn.extras); !p.empty()) out.properties[&inner] = std::move(p);
    if (sx && sx->Has("mask")) {
        const double mask = number(*sx, "mask", xp, 0);
        if (mask < 0 || mask > 4294967295.0 || mask != std::floor(mask))
            bad(xp + ".mask", "must be a 32-bit unsigned integer");
        inner.setNodeMask(uint32_t(mask));
    }
    if (sx && sx->Has("feature")) nodeFeature(inner, sx->Get("feature"), xp + ".feature");
}

void Converter::addMesh(int i, const std::string& kind, const Value* sx, const std::string& xp, Node* inner,
                        const dmat4& world, const std::string& path, bool instancedLod,
                        const ref_ptr<LOD>& lodPrototype) {
    const tinygltf::Node& gn = m.nodes[size_t(i)];
    const bool instanced = instancing(gn) && gn.mesh >= 0 && (kind == "Transform" || instancedLod);
    if (instancing(gn) && !instanced)
        warn(path + ".extensions." + kInstancing,
             gn.mesh < 0 ? "needs a mesh to instance, ignored" : "on an sgkit " + kind + " node is ignored");
    if (gn.extensions.count(kInstanceFeatures) && !instanced)
        warn(path + ".extensions." + kInstanceFeatures, "without instances (EXT_mesh_gpu_instancing), ignored");
    const bool plain = gn.mesh >= 0 && kind == "Transform" && !instanced;
    if (gn.skin >= 0 && !plain && kind != "Geometry")
        warn(path + ".skin", gn.mesh < 0 ? "a skin without a mesh is ignored"
                                         : "a skin on an instanced or sgkit " + kind + " node is ignored");
    if (instanced) {
        if (lodPrototype) levelOfInstancedLod(*lodPrototype, gn, *sx, xp, path);
        instances(i, static_cast<Group*>(inner), world, path, lodPrototype);
    } else if (plain && (gn.skin >= 0 || targetCount(gn.mesh) > 0)) {
        ownGeometries(i, *static_cast<Group*>(inner), path);  // its weights and skin are its own
    } else if (plain) {
        for (const auto& g : geometries(gn.mesh))
            if (g) static_cast<Group*>(inner)->addChild(g);
    } else if (gn.mesh >= 0 && kind != "Geometry") {
        warn(path + ".mesh", "a " + kind + " node's mesh is ignored");
    }
}

void Converter::countExpanded(const Node* node, const Node* inner, const std::string& kind, const std::string& path) {
    // Shared nodes make a DAG whose paths a Scene expands: a small file must not stand for a huge scene.
    // (An Instance's prototype has an image of its own, counted where it was built.)
    uint64_t size = 1;
    if (kind != "Instance")
        for (size_t k = 0; k < inner->numChildren(); ++k) size += expanded(inner->child(k));
    if (inner != node) ++size;
    if (size > kMaxExpandedNodes)
        bad(path, "the graph below expands to more than " + std::to_string(kMaxExpandedNodes) +
                      " nodes (shared subgraphs, one entry per path)");
    expandedSize[node] = size;
}

uint64_t Converter::expanded(const Node* n) const {
    auto it = expandedSize.find(n);
    return it == expandedSize.end() ? 1 : it->second;  // a Geometry shared per glTF mesh
}

void Converter::children(const tinygltf::Node& gn, const std::string& kind, const Value* sx, const std::string& xp,
                         Node* inner, const dmat4& world, const std::string& path) {
    if (gn.children.empty()) return;
    if (kind == "Geometry" || kind == "Occluder") {
        warn(path + ".children", "a " + kind + " node has no children, they are ignored");
        return;
    }
    if (kind == "Instance") {
        if (gn.children.size() != 1)
            bad(path + ".children", "an sgkit Instance needs exactly one child, its prototype");
        ref_ptr<Node> proto = build(gn.children[0], world);
        try {
            if (proto) static_cast<Instance*>(inner)->setPrototype(proto);
        } catch (const std::invalid_argument& e) {
            bad(path + ".children[0]", e.what());
        }
        return;
    }
    const Value* ranges = kind == "LOD" && sx->Has("ranges") ? &sx->Get("ranges") : nullptr;
    const Value* errors = kind == "LOD" && sx->Has("errors") ? &sx->Get("errors") : nullptr;
    const Value* on = kind == "Switch" && sx->Has("on") ? &sx->Get("on") : nullptr;
    const size_t nc = gn.children.size();
    if (kind == "LOD" && (!ranges || !ranges->IsArray() || ranges->ArrayLen() != nc))
        bad(xp + ".ranges", "needs one [min, max] range per child (" + std::to_string(nc) + ")");
    if (errors && (!errors->IsArray() || errors->ArrayLen() != nc))
        bad(xp + ".errors", "needs one error per child (" + std::to_string(nc) + ")");
    if (on && (!on->IsArray() || on->ArrayLen() != nc))
        bad(xp + ".on", "needs one flag per child (" + std::to_string(nc) + ")");
    auto* group = static_cast<Group*>(inner);
    for (size_t k = 0; k < nc; ++k) {
        ref_ptr<Node> c = build(gn.children[k], world);
        if (!c) continue;
        try {
            if (kind == "LOD") {
                addLevel(*static_cast<LOD*>(inner), c, *sx, xp, k, nc);
            } else if (kind == "Switch") {
                const Value& f = on ? on->Get(int(k)) : Value(true);
                if (!f.IsBool()) bad(at(xp + ".on", k), "must be true or false");
                static_cast<Switch*>(inner)->addChild(c, f.Get<bool>());
            } else {
                group->addChild(c);
            }
        } catch (const std::invalid_argument& e) {
            bad(at(path + ".children", k), e.what());
        }
    }
}

void Converter::extensionWarnings() {
    const auto& required = m.extensionsRequired;
    for (size_t i = 0; i < required.size(); ++i)  // others validate() has refused
        if (!supportedExtension(required[i])) {
            const bool image = required[i] == "KHR_texture_basisu" || required[i] == "EXT_texture_webp";
            warn(at("extensionsRequired", i), "extension '" + required[i] + "' is not supported: " +
                                                  (image ? "its textures are not decoded, drawn untextured"
                                                         : "drawn with the nearest material sgkit has"));
        }
    for (size_t i = 0; i < m.extensionsUsed.size(); ++i) {
        const std::string& e = m.extensionsUsed[i];
        if (!supportedExtension(e) && std::find(required.begin(), required.end(), e) == required.end())
            warn(at("extensionsUsed", i), "extension '" + e + "' is not supported, ignored");
    }
}

GltfScene convert(const std::string& file, const tinygltf::Model& model, Progress& progress,
                  std::vector<std::string> warnings, std::vector<bool> noData) {
    Converter c(file, model, progress);
    c.out.warnings = std::move(warnings);
    c.noData = std::move(noData);
    auto root = make<Group>();
    std::vector<int> roots;
    const int scene = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
    if (scene >= 0) {
        roots = model.scenes[size_t(scene)].nodes;
        root->setName(model.scenes[size_t(scene)].name);
        c.out.sceneProperties = properties(model.scenes[size_t(scene)].extras);
    } else {  // no scene: every root node
        std::vector<bool> child(model.nodes.size());
        for (const auto& n : model.nodes)
            for (int k : n.children) child[size_t(k)] = true;
        for (size_t i = 0; i < model.nodes.size(); ++i)
            if (!child[i]) roots.push_back(int(i));
    }
    c.extensionWarnings();
    c.readMetadata();
    progress.report(0.6, "converting");
    c.nodeOf.resize(model.nodes.size());
    for (int r : roots)
        if (ref_ptr<Node> n = c.build(r, dmat4(1.0))) root->addChild(n);
    c.skins(*root);  // joints are nodes of the whole tree
    c.animations();
    c.out.nodes = c.nodeOf;
    c.out.root = root;
    progress.report(1.0, "done");
    return std::move(c.out);
}

}  // namespace sg::gltf
