// A tile's content with its repeated leaves placed as Instances (which saveGltf writes with
// EXT_mesh_gpu_instancing): a city's tile holds tens of thousands of cells, each the same few nodes over one of a
// few dozen meshes, and a glTF node per node made such a tile tens of megabytes of JSON that took seconds to read.
#include "loaders/tiles/internal/TilesetDetail.h"

#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/core/Features.h"

#include <map>
#include <set>
#include <tuple>

namespace sg::tiles {
namespace {

bool plain(const Node& n) { return n.name().empty() && n.nodeMask() == 0xffffffffu; }
// A node whose feature binding (Node::setFeatures: a building) the Instance placing it cannot take over: one
// inside the shared prototype would name one feature for every placement.
bool bare(const Node& n) { return plain(n) && !n.features(); }

bool drawnGeometry(const Node* n) {
    if (!n || n->kind() != NodeKind::Geometry || !plain(*n)) return false;
    const Mesh* m = static_cast<const Geometry*>(n)->mesh();
    return m && m->primitiveCount() > 0;
}

// What makes two leaves the same prototype: the mesh and material, and for an LOD of that one level, everything
// the LOD holds. Centres are the user's (reduced LODs have one: TilesetContent.cpp fixes it).
using Key =
    std::tuple<const Mesh*, const Material*, bool, int, double, double, double, float, float, float, bool, float>;

bool instancable(const Node* n) {
    if (drawnGeometry(n)) return true;
    if (!n || n->kind() != NodeKind::LOD || !plain(*n) || n->numChildren() != 1) return false;
    return static_cast<const LOD*>(n)->userCenter() && drawnGeometry(n->child(0)) && bare(*n->child(0));
}

Key keyOf(const Node& n) {
    const bool lod = n.kind() == NodeKind::LOD;
    const auto& g = static_cast<const Geometry&>(lod ? *n.child(0) : n);
    if (!lod) return Key{g.mesh(), g.material(), false, 0, 0, 0, 0, 0, 0, 0, false, 0};
    const auto& l = static_cast<const LOD&>(n);
    return Key{g.mesh(),       g.material(),   true,          int(l.mode()),
               l.center().x,   l.center().y,   l.center().z,  l.transition(),
               l.range(0).min, l.range(0).max, l.hasErrors(), l.hasErrors() ? l.error(0) : 0.0f};
}

ref_ptr<Node> prototypeOf(const Node& n) {
    const bool lod = n.kind() == NodeKind::LOD;
    const auto& g = static_cast<const Geometry&>(lod ? *n.child(0) : n);
    auto geometry = make<Geometry>(ref_ptr<Mesh>(g.mesh()), ref_ptr<Material>(g.material()));
    if (!lod) return geometry;
    const auto& l = static_cast<const LOD&>(n);
    auto copy = make<LOD>();
    copy->setMode(l.mode());
    copy->setCenter(l.center());
    if (l.transition() > 0.0f) copy->setTransition(l.transition());
    copy->addChild(geometry, l.range(0).min, l.range(0).max);
    if (l.hasErrors()) copy->setError(0, l.error(0));
    return copy;
}

struct Leaf {
    Group* parent;  // holds `node`, which goes
    Node* node;     // the leaf, or a Transform over it
    const Node* drawn;
    dmat4 place;          // the leaf's frame in the content's
    const Node* feature;  // `node` or `drawn` when it is a feature (Node::setFeatures); the Instance becomes it
};

// A leaf, unless both its Transform and what it places are features: an Instance is one feature.
void addLeaf(Group& parent, Node* node, const Node* drawn, const dmat4& place, std::vector<Leaf>& out) {
    if (node != drawn && node->features() && drawn->features()) return;
    out.push_back({&parent, node, drawn, place, node->features() ? node : drawn->features() ? drawn : nullptr});
}

void collect(Group& n, const dmat4& m, std::vector<Leaf>& out) {
    for (size_t i = 0; i < n.numChildren(); ++i) {
        Node* c = n.child(i);
        if (!c || !plain(*c)) continue;
        if (instancable(c)) {
            addLeaf(n, c, c, m, out);
        } else if (c->kind() == NodeKind::Transform) {
            const dmat4 cm = m * static_cast<const Transform*>(c)->matrix();
            if (c->numChildren() == 1 && instancable(c->child(0)))
                addLeaf(n, c, c->child(0), cm, out);
            else if (!c->features())  // a feature of many parts stays whole, its binding with it
                collect(*static_cast<Group*>(c), cm, out);
        } else if (c->kind() == NodeKind::Group && !c->features()) {
            collect(*static_cast<Group*>(c), m, out);
        }
    }
}

// Drops the children in `gone`, and the Groups and Transforms that it leaves empty; true if `n` changed.
bool prune(Group& n, const std::set<const Node*>& gone) {
    std::vector<ref_ptr<Node>> kept;
    bool changed = false;
    for (size_t i = 0; i < n.numChildren(); ++i) {
        Node* c = n.child(i);
        const bool container = c && (c->kind() == NodeKind::Group || c->kind() == NodeKind::Transform);
        if (gone.count(c) || (container && prune(*static_cast<Group*>(c), gone) && c->numChildren() == 0)) {
            changed = true;
            continue;
        }
        kept.push_back(ref_ptr<Node>(c));
    }
    if (changed) {
        n.removeAllChildren();
        for (auto& c : kept) n.addChild(std::move(c));
    }
    return changed;
}

}  // namespace

size_t instanceRepeats(Group& content) {
    std::vector<Leaf> leaves;
    collect(content, dmat4(1.0), leaves);
    std::map<Key, std::vector<const Leaf*>> byKey;
    for (const Leaf& l : leaves) byKey[keyOf(*l.drawn)].push_back(&l);
    std::set<const Node*> gone;
    std::vector<ref_ptr<Node>> placed;
    for (const auto& [key, same] : byKey) {
        if (same.size() < 2) continue;
        const ref_ptr<Node> proto = prototypeOf(*same.front()->drawn);
        for (const Leaf* l : same) {
            auto instance = make<Instance>(proto, l->place);
            if (l->feature)
                instance->setFeatures(ref_ptr<const MeshFeatures>(l->feature->features()), l->feature->featureIndex());
            placed.push_back(std::move(instance));
            gone.insert(l->node);
        }
    }
    if (gone.empty()) return 0;
    prune(content, gone);
    for (auto& p : placed) content.addChild(std::move(p));
    return placed.size();
}

}  // namespace sg::tiles
