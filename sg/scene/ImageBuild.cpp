// Scene::Builder's passes over an image: a full build (its layout: entries counted, an origin picked, tables
// emptied, then every entry written), a refit of the dirty paths in place, the chunk boxes over the occluders, a
// Switch's bits copied alone, and the dirty marks cleared.
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/Transform.h"
#include "sg/scene/internal/ImageBounds.h"
#include "sg/scene/internal/ImageBuilder.h"

#include <algorithm>
#include <unordered_set>

namespace sg {

// Inline (ImageBuilder.h says why): runs once per node of a full build.
inline void Scene::Builder::count(const Node* n, Counts& c) {
    c.entries++;
    switch (n->kind()) {
        case NodeKind::Instance: return;  // the prototype has its own image
        case NodeKind::Transform: c.xforms++; break;
        case NodeKind::LOD: c.lods++; break;
        default: break;
    }
    const Node* skip = detailOf(n);
    for (size_t i = 0, k = n->numChildren(); i < k; ++i)
        if (n->child(i) != skip) count(n->child(i), c);
}

// A point inside the scene, found by one descent: float offsets from it stay small.
inline dvec3 Scene::Builder::pickOrigin(const Node* n) {
    dmat4 m(1.0);
    for (int depth = 0; n && depth < 4096; ++depth) {
        if (n->kind() == NodeKind::Transform) m = static_cast<const Transform*>(n)->apply(m);
        if (n->kind() == NodeKind::Instance) m = m * static_cast<const Instance*>(n)->matrix();
        if (n->kind() == NodeKind::Geometry) {
            const Mesh* mesh = static_cast<const Geometry*>(n)->mesh();
            if (mesh && mesh->validBound() && !mesh->box().empty()) return dvec3(m * dvec4(mesh->box().center(), 1));
        }
        n = n->numChildren() ? n->child(0) : nullptr;
    }
    const dvec3 t(m[3]);
    return isFinite(t) ? t : dvec3(0.0);
}

// The image of `root` placed by `frame` (the identity, but for a paged detail: its PagedLOD's frame).
void Scene::Builder::full(Node* root, const dmat4& frame) {
    img.origin = dvec3(frame * dvec4(pickOrigin(root), 1.0));
    Counts c;
    count(root, c);
    img.resize(c.entries);
    // The tables are filled in order and rewritten in place by later refits. Translations and LODs get
    // one allocation of the counted size (for translations an upper bound: general matrices go to
    // `matrices`), replacing any larger one a previous build left; the other tables grow as filled.
    img.matrices.clear(), img.switchOn.clear(), img.nodes.clear(), img.masked.clear(), img.placements.clear();
    img.featured.clear(), img.posed.clear();
    img.translations = {}, img.translations.reserve(c.xforms);
    img.lods = {}, img.lods.reserve(c.lods);
    img.ranges.clear(), img.paged.clear(), img.draws.clear(), img.drawIndex.clear(), img.rangeIndex.clear();
    img.wides.clear(), img.wideEntry.clear(), img.wcx.clear(), img.wcy.clear(), img.wcz.clear(), img.wr.clear();
    img.occluders.clear(), img.occluderMatrices.clear(), img.occluderChunks.clear();
    img.occluderSwitchBits.clear();
    img.prototypes.clear();  // rebuilt as met: no prototype left out of the structure keeps its image
    fresh = true;
    cursor = 0;
    prevSibling = nullptr;
    write(root, frame);
    updateExtent();
    if (!detail) scene.stats_.fullRebuilds++;
}

void Scene::Builder::updateExtent() {
    img.extent = 0.0;
    if (img.size() == 0) return;
    if (img.flags[0] & (FlatImage::kInvalid)) {  // some entry below is invalid: scan the valid ones
        for (size_t i = 0; i < img.size(); ++i)
            if (!(img.flags[i] & (FlatImage::kInvalid | FlatImage::kEmpty)))
                img.extent = std::max(img.extent, glm::length(img.center(i) - img.origin) + img.r[i]);
    } else {
        img.extent = glm::length(img.center(0) - img.origin) + img.r[0];
    }
}

// Structure unchanged: rewrite only the dirty paths in place.
void Scene::Builder::refit(uint32_t i, Node* n, const dmat4& m) {
    if ((n->dirtyBits() & Node::kDirtyBound) || n->kind() == NodeKind::Billboard || n->kind() == NodeKind::Instance) {
        cursor = i;
        prevSibling = nullptr;  // not the parent's walk: an occluder written alone keeps its LOD's entry
        write(n, m);
        return;
    }
    const dmat4 cm = n->kind() == NodeKind::Transform ? static_cast<Transform*>(n)->apply(m) : m;
    const int cond = isConditional(n);
    conditional += cond;
    uint32_t j = i + 1;
    const Node* skip = detailOf(n);
    for (size_t k = 0, c = n->numChildren(); k < c; ++k) {
        Node* ch = n->child(k);
        if (ch == skip) continue;
        if (ch->dirtyBits()) {
            const int pushed = enter(i, n, k);
            refit(j, ch, cm);
            leave(n, pushed);
        }
        j = img.end[j];
    }
    conditional -= cond;
    boundFromChildren(i);
    wide(i, n);
    if (n->kind() == NodeKind::LOD) lodCenter(i, static_cast<const LOD*>(n), cm);
    if (n->kind() == NodeKind::PagedLOD) paged(i, static_cast<const PagedLOD*>(n), cm, false);
    if (n->kind() == NodeKind::BspGroup) bsp(i, n, cm);
}

// Chunk boxes over the active occluders, tested against the frustum before the occluders themselves.
void Scene::Builder::occluderChunks() {
    const uint32_t k = FlatImage::kOccluderChunk, n = uint32_t(img.occluders.size());
    img.occluderChunks.assign((n + k - 1) / k, Box{});
    for (uint32_t j = 0; j < n; ++j) {
        const FlatImage::OccluderRef& o = img.occluders[j];
        if (o.active && !(img.flags[o.entry] & (FlatImage::kEmpty | FlatImage::kInvalid)))
            img.occluderChunks[j / k].expand(img.box(o.entry));
    }
}

// A Switch turned below n (entry i), with no refit to rewrite its entry: follows the kDirtyChoice marks down,
// into Instance prototypes' and paged details' images too, and copies the bits of the Switches met. A
// prototype placed many times is met once per path: the copy is the same each time.
void Scene::Builder::choices(uint32_t i, Node* n) {
    if (n->kind() == NodeKind::Switch) switchBits(i, n);
    if (n->kind() == NodeKind::Instance) {
        Node* p = static_cast<Instance*>(n)->prototype();
        if (!p || !p->choiceChanged()) return;
        auto& table = detail ? img.prototypes : scene.protos_;
        auto it = table.find(p);
        if (it == table.end() || !it->second || it->second->size() == 0) return;
        std::unordered_set<const Node*> built;
        Builder b{scene, *it->second, built};
        b.detail = detail;
        b.choices(0, p);
        return;
    }
    const Node* skip = detailOf(n);
    if (skip && skip->choiceChanged()) {
        const FlatImage::Paged& pg = img.paged[img.aux[i]];
        if (pg.detail && pg.detail->size()) {
            std::unordered_set<const Node*> built;
            Builder b{scene, *pg.detail, built};
            b.detail = true;
            b.choices(0, const_cast<Node*>(skip));
        }
    }
    uint32_t j = i + 1;
    for (size_t k = 0, c = n->numChildren(); k < c; ++k) {
        Node* ch = n->child(k);
        if (ch == skip) continue;
        if (ch->choiceChanged()) choices(j, ch);
        j = img.end[j];
    }
}

void Scene::Builder::clear(Node* n) {
    if (!n->dirtyBits() && !n->choiceChanged()) return;
    n->clearDirty();
    for (size_t k = 0, c = n->numChildren(); k < c; ++k) clear(n->child(k));
}

}  // namespace sg
