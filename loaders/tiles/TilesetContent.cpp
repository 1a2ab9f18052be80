// writeTileset's view of the scene: units, triangle counts, bounds, and the graph a tile's content holds (a
// copy of its units with LODs reduced, or a merged and simplified proxy).
#include "loaders/tiles/internal/TilesetDetail.h"

#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/build/LodGenerator.h"
#include "sg/core/Features.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace sg::tiles {
namespace {

// The child of a distance LOD that shows nearest, or of a pixel-size LOD that shows largest.
size_t finestChild(const LOD& lod) {
    size_t best = 0;
    for (size_t i = 1; i < lod.numChildren(); ++i)
        if (lod.mode() == LOD::Mode::Distance ? lod.range(i).min < lod.range(best).min
                                              : lod.range(i).max > lod.range(best).max)
            best = i;
    return best;
}

// The distance up to which child i of a distance LOD may show, its fade band included.
double reachOf(const LOD& lod, size_t i) { return double(lod.range(i).max) + 0.5 * double(lod.transition()); }

// Whether a reduction at `d` keeps child i: children that cannot show beyond d are dropped. kKeepAll keeps all.
bool keeps(const LOD& lod, size_t i, double d) {
    return d == kKeepAll || lod.mode() != LOD::Mode::Distance || reachOf(lod, i) > d;
}

// Kinds copied node by node (and so reduced); the others are referenced whole (see addUnit).
bool copied(NodeKind k) {
    return k == NodeKind::Group || k == NodeKind::Transform || k == NodeKind::Geometry || k == NodeKind::LOD ||
           k == NodeKind::Switch;
}

uint64_t meshTriangles(const Node& n) {
    const Mesh* m = static_cast<const Geometry&>(n).mesh();
    return m ? m->triangleCount() : 0;
}

// The world bound the cull would give the node (a Billboard's: the sphere its children sweep), plus the centres
// of distance LODs, which the exactness argument needs inside the tile (writeTileset).
void expandBound(Box& b, const Node& n, const dmat4& world) {
    switch (n.kind()) {
        case NodeKind::Geometry:
            if (const Mesh* m = static_cast<const Geometry&>(n).mesh(); m && m->validBound())
                b.expand(transformBox(world, m->box()));
            return;
        case NodeKind::Occluder: return;  // not drawn
        case NodeKind::Transform: {
            const dmat4 w = world * static_cast<const Transform&>(n).matrix();
            for (size_t i = 0; i < n.numChildren(); ++i) expandBound(b, *n.child(i), w);
            return;
        }
        case NodeKind::Instance: {
            const auto& in = static_cast<const Instance&>(n);
            if (in.prototype()) expandBound(b, *in.prototype(), world * in.matrix());
            return;
        }
        case NodeKind::Billboard: {
            Box local;
            for (size_t i = 0; i < n.numChildren(); ++i) expandBound(local, *n.child(i), dmat4(1.0));
            if (local.empty()) return;
            const double r = std::max(glm::length(local.min), glm::length(local.max));
            b.expand(transformBox(world, Box{dvec3(-r), dvec3(r)}));
            return;
        }
        case NodeKind::LOD: {
            const auto& lod = static_cast<const LOD&>(n);
            if (lod.userCenter()) b.expand(dvec3(world * dvec4(lod.center(), 1.0)));
            break;
        }
        default: break;
    }
    const Node* detail = n.kind() == NodeKind::PagedLOD ? static_cast<const PagedLOD&>(n).detail() : nullptr;
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Node* c = n.child(i); c && c != detail) expandBound(b, *c, world);
}

uint64_t finestTriangles(const Node& n) {
    if (n.kind() == NodeKind::Geometry) return meshTriangles(n);
    if (n.kind() == NodeKind::LOD) {
        const auto& lod = static_cast<const LOD&>(n);
        return lod.numChildren() ? finestTriangles(*lod.child(finestChild(lod))) : 0;
    }
    const Node* detail = n.kind() == NodeKind::PagedLOD ? static_cast<const PagedLOD&>(n).detail() : nullptr;
    uint64_t t = 0;
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Node* c = n.child(i); c && c != detail) t += finestTriangles(*c);
    return t;
}

// The largest reach of the finest child of the distance LODs that addUnit copies (those it can reduce); an
// infinite reach is left out, as nothing can be dropped below it.
double reachBelow(const Node& n) {
    if (!copied(n.kind())) return 0.0;
    double r = 0.0;
    if (n.kind() == NodeKind::LOD) {
        const auto& lod = static_cast<const LOD&>(n);
        if (lod.mode() == LOD::Mode::Distance && lod.numChildren()) {
            const double f = reachOf(lod, finestChild(lod));
            if (std::isfinite(f)) r = f;
        }
    }
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Node* c = n.child(i)) r = std::max(r, reachBelow(*c));
    return r;
}

void collect(Units& u, const Node& n, uint32_t above, uint64_t unitTriangles) {
    // A feature (Node::setFeatures) stays one unit: split, its parts would be copied without its binding.
    const bool splittable = (n.kind() == NodeKind::Group || n.kind() == NodeKind::Transform) && !n.features();
    if (splittable && n.numChildren() > 0 && finestTriangles(n) > unitTriangles) {
        uint32_t frame = above;
        if (n.kind() == NodeKind::Transform) {
            u.matrices.push_back(u.matrices[above] * static_cast<const Transform&>(n).matrix());
            frame = uint32_t(u.matrices.size() - 1);
        }
        for (size_t i = 0; i < n.numChildren(); ++i)
            if (const Node* c = n.child(i)) collect(u, *c, frame, unitTriangles);
        return;
    }
    Unit unit;
    unit.node = &n;
    unit.above = above;
    expandBound(unit.box, n, u.matrices[above]);
    unit.triangles = finestTriangles(n);
    unit.reach = reachBelow(n);
    u.units.push_back(unit);
}

// A copy of `n` for a tile's content. `pending` (the world above n into the tile's frame) is folded into the
// first Transform met, or into a Transform made for a node that cannot hold it; `world` is n's original parent
// frame (for LOD centres). Shared meshes and materials stay shared, so that saveGltf writes each once per file.
ref_ptr<Node> copyNode(const Node& n, const dmat4& world, const dmat4& pending, double d) {
    const bool identity = pending == dmat4(1.0);
    auto wrap = [&](ref_ptr<Node> node) -> ref_ptr<Node> {
        if (identity) return node;
        auto t = make<Transform>(pending);
        t->addChild(std::move(node));
        return t;
    };
    // What the node says of itself goes with the copy: its name, mask and feature binding (a building's).
    auto named = [&](Node& c) {
        if (!n.name().empty()) c.setName(n.name());
        if (n.nodeMask() != 0xffffffffu) c.setNodeMask(n.nodeMask());
        if (n.features()) c.setFeatures(ref_ptr<const MeshFeatures>(n.features()), n.featureIndex());
    };
    switch (n.kind()) {
        case NodeKind::Transform: {
            const dmat4 m = static_cast<const Transform&>(n).matrix();
            auto t = make<Transform>(pending * m);
            named(*t);
            for (size_t i = 0; i < n.numChildren(); ++i)
                if (const Node* c = n.child(i)) t->addChild(copyNode(*c, world * m, dmat4(1.0), d));
            return t;
        }
        case NodeKind::Group: {
            auto g = make<Group>();
            named(*g);
            for (size_t i = 0; i < n.numChildren(); ++i)
                if (const Node* c = n.child(i)) g->addChild(copyNode(*c, world, pending, d));
            return g;
        }
        case NodeKind::Geometry: {
            const auto& g = static_cast<const Geometry&>(n);
            auto c = make<Geometry>(ref_ptr<Mesh>(g.mesh()), ref_ptr<Material>(g.material()));
            named(*c);
            return wrap(c);
        }
        case NodeKind::Switch: {
            const auto& s = static_cast<const Switch&>(n);
            auto c = make<Switch>();
            named(*c);
            for (size_t i = 0; i < s.numChildren(); ++i)
                c->addChild(copyNode(*s.child(i), world, dmat4(1.0), d), s.isOn(i));
            return wrap(c);
        }
        case NodeKind::LOD: {
            const auto& lod = static_cast<const LOD&>(n);
            auto c = make<LOD>();
            named(*c);
            c->setMode(lod.mode());
            if (lod.transition() > 0.0f) c->setTransition(lod.transition());
            bool dropped = false;
            for (size_t i = 0; i < lod.numChildren(); ++i) {
                if (!keeps(lod, i, d)) {
                    dropped = true;
                    continue;
                }
                c->addChild(copyNode(*lod.child(i), world, dmat4(1.0), d), lod.range(i).min, lod.range(i).max);
                if (lod.hasErrors()) c->setError(c->numChildren() - 1, lod.error(i));
            }
            if (lod.userCenter()) {
                c->setCenter(lod.center());
            } else if (dropped) {
                // The default centre is the bound's: fixed at the full LOD's, or the reduced one would switch
                // elsewhere. The cull takes the centre of the world box; mapped back into the LOD's frame.
                Box b;
                expandBound(b, lod, world);
                if (!b.empty()) c->setCenter(dvec3(glm::inverse(world) * dvec4(b.center(), 1.0)));
            }
            return wrap(c);
        }
        default:
            // Billboards, Instances, BSP groups, occluders and paged LODs are referenced, not copied: written
            // whole by saveGltf (a second parent only while the content exists, on the writing thread).
            return wrap(ref_ptr<Node>(const_cast<Node*>(&n)));
    }
}

void finest(Proxy& p, const Node& n, dmat4 m, size_t& skipped) {
    switch (n.kind()) {
        case NodeKind::Geometry: {
            const auto& g = static_cast<const Geometry&>(n);
            const Mesh* mesh = g.mesh();
            if (!mesh || mesh->triangleCount() == 0) return;
            auto it = std::find_if(p.parts.begin(), p.parts.end(),
                                   [&](const ProxyPart& q) { return q.material == g.material(); });
            if (it == p.parts.end()) {
                p.parts.emplace_back();
                p.parts.back().material = g.material();
                it = p.parts.end() - 1;
            }
            const glm::dmat3 nm = glm::transpose(glm::inverse(glm::dmat3(m)));
            const auto base = uint32_t(it->positions.size());
            for (size_t i = 0; i < mesh->positions().size(); ++i) {
                it->positions.push_back(vec3(m * dvec4(dvec3(mesh->positions()[i]), 1.0)));
                const dvec3 nrm = mesh->normals().empty() ? dvec3(0, 0, 1) : nm * dvec3(mesh->normals()[i]);
                it->normals.push_back(vec3(glm::length(nrm) > 0 ? glm::normalize(nrm) : nrm));
            }
            for (uint32_t i = 0; i < mesh->indexCount(); ++i) it->indices.push_back(base + mesh->index(i));
            return;
        }
        case NodeKind::Transform: m = m * static_cast<const Transform&>(n).matrix(); break;
        case NodeKind::Instance: {
            const auto& in = static_cast<const Instance&>(n);
            if (in.prototype()) finest(p, *in.prototype(), m * in.matrix(), skipped);
            return;
        }
        case NodeKind::LOD: {
            const auto& lod = static_cast<const LOD&>(n);
            if (lod.numChildren()) finest(p, *lod.child(finestChild(lod)), m, skipped);
            return;
        }
        case NodeKind::Switch: {
            const auto& s = static_cast<const Switch&>(n);
            for (size_t i = 0; i < s.numChildren(); ++i)
                if (s.isOn(i)) finest(p, *s.child(i), m, skipped);
            return;
        }
        case NodeKind::Billboard: ++skipped; return;
        case NodeKind::Occluder: return;
        default: break;
    }
    const Node* detail = n.kind() == NodeKind::PagedLOD ? static_cast<const PagedLOD&>(n).detail() : nullptr;
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Node* c = n.child(i); c && c != detail) finest(p, *c, m, skipped);
}

}  // namespace

Units collectUnits(const Node& root, uint64_t unitTriangles) {
    Units u;
    collect(u, root, 0, unitTriangles);
    return u;
}

uint64_t reducedTriangles(const Node& n, double d, uint64_t limit) {
    if (n.kind() == NodeKind::Geometry) return meshTriangles(n);
    if (!copied(n.kind())) return finestTriangles(n);
    if (n.kind() == NodeKind::LOD) {
        const auto& lod = static_cast<const LOD&>(n);
        // The finest child kept: the one with the smallest range start among those kept (distance LODs).
        size_t best = lod.numChildren();
        for (size_t i = 0; i < lod.numChildren(); ++i)
            if (keeps(lod, i, d) && (best == lod.numChildren() ||
                                     (lod.mode() == LOD::Mode::Distance ? lod.range(i).min < lod.range(best).min
                                                                        : lod.range(i).max > lod.range(best).max)))
                best = i;
        return best < lod.numChildren() ? reducedTriangles(*lod.child(best), d, limit) : 0;
    }
    uint64_t t = 0;
    for (size_t i = 0; i < n.numChildren() && t <= limit; ++i)
        if (const Node* c = n.child(i)) t += reducedTriangles(*c, d, limit - t);
    return t;
}

void addUnit(Group& content, const Node& unit, const dmat4& world, const dmat4& toTile, double d) {
    content.addChild(copyNode(unit, world, toTile * world, d));
}

uint64_t Proxy::triangles() const {
    uint64_t t = 0;
    for (const ProxyPart& q : parts) t += q.indices.size() / 3;
    return t;
}

void addFinest(Proxy& proxy, const Node& unit, const dmat4& world, size_t& skipped) {
    finest(proxy, unit, glm::translate(dmat4(1.0), -proxy.centre) * world, skipped);
}

Proxy simplifyMerged(const std::vector<Proxy>& children, const dvec3& centre, uint64_t target) {
    Proxy out;
    out.centre = centre;
    std::map<const Material*, ProxyPart> merged;
    double childError = 0.0;
    for (const Proxy& c : children) {
        childError = std::max(childError, c.error);
        const vec3 shift(c.centre - centre);
        for (const ProxyPart& q : c.parts) {
            ProxyPart& m = merged[q.material];
            m.material = q.material;
            const auto base = uint32_t(m.positions.size());
            for (const vec3& p : q.positions) m.positions.push_back(p + shift);
            m.normals.insert(m.normals.end(), q.normals.begin(), q.normals.end());
            for (uint32_t i : q.indices) m.indices.push_back(base + i);
        }
    }
    uint64_t total = 0;
    for (const auto& [mat, q] : merged) total += q.indices.size() / 3;
    const double ratio = total > 0 ? double(target) / double(total) : 1.0;
    double error = 0.0;
    for (auto& [mat, q] : merged) {
        if (ratio < 1.0 && q.indices.size() >= 6) {
            auto mesh = make<Mesh>();
            mesh->set(std::move(q.positions), std::move(q.normals), std::move(q.indices));
            const auto levels = generateLevels(mesh, {float(std::max(ratio, 1e-6))});
            const Mesh& s = *levels[1].mesh;
            error = std::max(error, double(levels[1].error));
            q.positions = s.positions();
            q.normals = s.normals();
            q.indices.clear();
            for (uint32_t i = 0; i < s.indexCount(); ++i) q.indices.push_back(s.index(i));
        }
        out.parts.push_back(std::move(q));
    }
    // The simplifier measures against its input, itself already simplified: the deviations add up.
    out.error = childError + error;
    return out;
}

void addProxy(Group& content, const Proxy& proxy) {
    for (const ProxyPart& q : proxy.parts) {
        if (q.indices.empty()) continue;
        auto mesh = make<Mesh>();
        mesh->set(q.positions, q.normals, q.indices);
        content.addChild(make<Geometry>(mesh, ref_ptr<Material>(const_cast<Material*>(q.material))));
    }
}

}  // namespace sg::tiles
