// An image entry written: write() runs the steps every node shares, then its kind's handler. The helpers are
// inline: write() runs them once per entry (ImageBuilder.h says why).
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/Occluder.h"
#include "nodes/Sequence.h"
#include "nodes/Transform.h"
#include "sg/scene/internal/ImageBounds.h"
#include "sg/scene/internal/ImageBuilder.h"

#include <algorithm>
#include <limits>
#include <tuple>

namespace sg {

// The mask is copied (setNodeMask() marks kDirtyBound, which rewrites the entry): the application may set it
// again while a cull reads this image.
inline void Scene::Builder::setMasked(uint32_t i, const Node* n) {
    auto& v = img.masked;
    auto it = std::lower_bound(v.begin(), v.end(), std::make_pair(i, 0u));
    const bool present = it != v.end() && it->first == i;
    if (n->nodeMask() != 0xffffffffu) {
        img.flags[i] |= FlatImage::kMasked;
        if (present)
            it->second = n->nodeMask();
        else
            v.insert(it, {i, n->nodeMask()});
    } else if (present) {
        v.erase(it);
    }
}

// The feature binding, held like the mask: Node::setFeatures() marks kDirtyBound, which rewrites the entry.
inline void Scene::Builder::setFeatured(uint32_t i, const Node* n) {
    auto& v = img.featured;
    auto it = std::lower_bound(v.begin(), v.end(), i, [](const auto& e, uint32_t k) { return e.first < k; });
    const bool present = it != v.end() && it->first == i;
    if (const MeshFeatures* f = n->features()) {
        img.flags[i] |= FlatImage::kFeature;
        FlatImage::FeatureRef ref{ref_ptr<const MeshFeatures>(f), n->featureIndex()};
        if (present)
            it->second = std::move(ref);
        else
            v.insert(it, {i, std::move(ref)});
    } else if (present) {
        v.erase(it);
    }
}

// Copies the parameters the cull reads into the kind's table: a handler per kind.
inline void Scene::Builder::params(uint32_t i, Node* n) {
    switch (n->kind()) {
        case NodeKind::Transform: return writeTransform(i, n);
        case NodeKind::Geometry: return writeGeometry(i, n);
        case NodeKind::LOD: return writeLod(i, n);
        case NodeKind::PagedLOD: return writePaged(i, n);
        case NodeKind::Instance:
            return writeInstance(i, n);  // the prototype's image is filled in by write(), once built
        case NodeKind::Group:
            if (fresh) img.aux[i] = 0;  // a wide Group's index is kept by refits
            return;
        case NodeKind::Occluder: return;  // written with its frame, in write()
        case NodeKind::Switch: return writeSwitch(i, n);
        default: img.aux[i] = slot(img.nodes, i, n); return;
    }
}

inline void Scene::Builder::writeTransform(uint32_t i, Node* n) {
    const auto* t = static_cast<const Transform*>(n);
    const bool wasGeneral = img.flags[i] & FlatImage::kGeneral;
    if (t->matrixPtr()) {  // a copy: the node frees its matrix when set again
        img.aux[i] = matrixSlot(wasGeneral ? img.aux[i] : FlatImage::kNone, *t->matrixPtr());
        img.flags[i] |= FlatImage::kGeneral;
    } else {
        img.aux[i] = slot(img.translations, i, t->translation(), !wasGeneral);
        img.flags[i] &= ~FlatImage::kGeneral;
    }
}

inline void Scene::Builder::writeGeometry(uint32_t i, Node* n) {
    const auto* g = static_cast<const Geometry*>(n);
    const auto key = std::make_pair<const Mesh*, const Material*>(g->mesh(), g->material());
    auto it = img.drawIndex.find(key);
    if (it == img.drawIndex.end()) {
        it = img.drawIndex.emplace(key, uint32_t(img.draws.size())).first;
        // A dense index over the scene's mesh/material pairs (all images): the sort's state.
        auto st = scene.states_.emplace(key, uint32_t(scene.states_.size())).first;
        img.draws.push_back(FlatImage::Draw{key.first, key.second, st->second});
    }
    img.aux[i] = it->second;  // shared, never rewritten: a changed geometry finds or adds its pair
}

inline void Scene::Builder::writeLod(uint32_t i, Node* n) {
    const auto* l = static_cast<const LOD*>(n);
    std::vector<float> key;
    for (size_t k = 0; k < l->numChildren(); ++k)
        key.insert(key.end(), {l->range(k).min, l->range(k).max, l->error(k)});
    auto it = img.rangeIndex.find(key);
    if (it == img.rangeIndex.end()) {
        it = img.rangeIndex.emplace(key, uint32_t(img.ranges.size())).first;
        for (size_t k = 0; k < key.size(); k += 3) img.ranges.push_back({key[k], key[k + 1], key[k + 2]});
    }
    // The centre is filled in by write(), once the bound and the frame are known.
    img.aux[i] =
        slot(img.lods, i,
             FlatImage::Lod{0.0f, 0.0f, 0.0f, it->second, l->transition(), uint8_t(l->mode()), l->hasErrors(), 0.0f});
}

inline void Scene::Builder::writePaged(uint32_t i, Node* n) {
    const auto* p = static_cast<const PagedLOD*>(n);
    // The centre and the detail's image are filled in by write(), once the bound and the frame are
    // known; a refit keeps the detail's image until then.
    std::shared_ptr<FlatImage> keep = fresh ? nullptr : img.paged[img.aux[i]].detail;
    // Refined by screen-space error: the value is pixels per unit, wanted from maxPixels / error up
    // (an error of 0 never refines).
    const bool sse = p->screenSpaceError();
    const float mn = !sse                        ? p->rangeMin()
                     : p->geometricError() > 0.0 ? float(p->maxScreenPixels() / p->geometricError())
                                                 : std::numeric_limits<float>::infinity();
    const uint8_t mode = sse ? FlatImage::kScreenError : uint8_t(p->mode());
    FlatImage::Paged pg{FlatImage::Lod{0.0f, 0.0f, 0.0f, 0, 0.0f, mode, false, 0.0f}, mn,
                        sse ? std::numeric_limits<float>::infinity() : p->rangeMax(), n, std::move(keep)};
    pg.plainPath = !prototype && conditional == described && n->nodeMask() == 0xffffffffu;
    pg.entry = i;
    const FlatImage::Paged* had = fresh ? nullptr : &img.paged[img.aux[i]];
    std::tie(pg.condFirst, pg.condCount) =
        storeConds(had ? had->condFirst : 0, had ? had->condCount : 0, had != nullptr);
    img.aux[i] = slot(img.paged, i, std::move(pg));
}

inline void Scene::Builder::writeInstance(uint32_t i, Node* n) {
    const dmat4& m = static_cast<const Instance*>(n)->matrix();
    const bool t = isTranslation(m);
    const uint32_t had = fresh ? FlatImage::kNone : img.placements[img.aux[i]].matrix;
    img.aux[i] =
        slot(img.placements, i,
             FlatImage::Placement{n, nullptr, t ? dvec3(m[3]) : dvec3(0.0), t ? FlatImage::kNone : matrixSlot(had, m)});
}

inline void Scene::Builder::writeSwitch(uint32_t i, Node* n) {
    if (fresh) {
        img.aux[i] = uint32_t(img.switchOn.size());
        img.switchOn.resize(img.switchOn.size() + n->numChildren());
    }
    switchBits(i, n);
}

// Writes the subtree of `n` at `cursor`; `m` is the world matrix of n's parent frame.
void Scene::Builder::write(Node* n, const dmat4& m) {
    const uint32_t i = cursor++;
    img.kind[i] = n->kind();
    img.flags[i] &= fresh ? 0 : FlatImage::kGeneral;  // a refit needs to know the transform's old table
    setMasked(i, n);
    setFeatured(i, n);
    params(i, n);
    scene.stats_.entriesWritten++;
    if (collect && n->updateCallback()) scene.callbacks_.push_back(n);
    if (collect && n->kind() == NodeKind::Switch)  // the kind first: a cast only for Switches, on full builds only
        if (auto* q = dynamic_cast<Sequence*>(n)) scene.sequences_.push_back(q);
    switch (n->kind()) {
        case NodeKind::Geometry: {
            auto* g = static_cast<Geometry*>(n);
            const Mesh* mesh = g->mesh();
            img.end[i] = cursor;
            if (mesh && g->posed()) return posed(i, g, m);  // ImagePoses.cpp
            dropPose(i);
            if (!mesh) return img.setBound(i, Box{}, 0.0);
            return leafBound(i, mesh->box(), mesh->validBound(), m);
        }
        case NodeKind::Occluder:
            img.end[i] = cursor;
            occluder(i, n, m);
            return leafBound(i, static_cast<Occluder*>(n)->box(), true, m);
        case NodeKind::Instance: {
            img.end[i] = cursor;
            auto* in = static_cast<Instance*>(n);
            if (!in->prototype()) return img.setBound(i, Box{}, 0.0);
            const FlatImage& p = proto(in->prototype());
            img.placements[img.aux[i]].proto = &p;
            if (p.size() == 0 || (p.flags[0] & FlatImage::kEmpty)) return img.setBound(i, Box{}, 0.0);
            const bool valid = !(p.flags[0] & FlatImage::kInvalid);
            // The prototype's root bound, in the prototype's frame (its image origin added back).
            const dmat4 pm = m * in->matrix();
            if (!valid) return img.setInvalid(i);
            img.setBound(i, transformBox(pm, p.box(0)), double(p.r[0]) * maxScale(pm));
            return;
        }
        default: break;
    }
    const dmat4 cm = n->kind() == NodeKind::Transform ? static_cast<Transform*>(n)->apply(m) : m;
    const int cond = isConditional(n);
    conditional += cond;
    const Node* skip = detailOf(n);
    const Node* before = nullptr;  // the last child written that is not an occluder, and its entry
    uint32_t beforeEntry = ~0u;
    for (size_t k = 0, c = n->numChildren(); k < c; ++k) {
        if (n->child(k) == skip) continue;
        // The last sibling before an occluder that is not one: the LOD a generated one may be shown with.
        prevSibling = before;
        prevSiblingEntry = beforeEntry;
        if (n->child(k)->kind() != NodeKind::Occluder) {  // an LOD's occluders follow it, one after another
            before = n->child(k);
            beforeEntry = cursor;
        }
        const int pushed = enter(i, n, k);
        write(n->child(k), cm);
        leave(n, pushed);
    }
    conditional -= cond;
    img.end[i] = cursor;
    boundFromChildren(i);
    wide(i, n);
    if (n->kind() == NodeKind::LOD) lodCenter(i, static_cast<const LOD*>(n), cm);
    if (n->kind() == NodeKind::PagedLOD) paged(i, static_cast<const PagedLOD*>(n), cm, true);
    if (n->kind() == NodeKind::Billboard) billboard(i, n, cm);
    if (n->kind() == NodeKind::BspGroup) bsp(i, n, cm);
}

// The occluder's frame, and whether the occlusion pass may use it.
inline void Scene::Builder::occluder(uint32_t i, const Node* n, const dmat4& m) {
    FlatImage::OccluderRef ref{n, i, ~0u, dvec3(m[3]),
                               !prototype && conditional == described && n->nodeMask() == 0xffffffffu};
    const auto* oc = static_cast<const Occluder*>(n);
    const FlatImage::OccluderRef* had = fresh ? nullptr : &img.occluders[img.aux[i]];
    std::tie(ref.switchFirst, ref.switchCount) =
        storeConds(had ? had->switchFirst : 0, had ? had->switchCount : 0, had != nullptr);
    ref.underPaged = underPaged();
    ref.conditional = oc->oneSided() || !oc->eyeOutside().empty() || !oc->openings().empty() || oc->shownWith() ||
                      oc->belowSurface() || ref.switchCount;
    if (oc->shownWith()) {
        // Written by its parent's walk, the LOD just before it is known; a refit of the occluder alone keeps
        // the entry it had (entries do not move in a refit).
        if (prevSibling == oc->shownWith())
            ref.lod = prevSiblingEntry;
        else if (!fresh && prevSibling == nullptr)
            ref.lod = img.occluders[img.aux[i]].lod;
        ref.active = ref.active && ref.lod != ~0u;
    }
    if (glm::dmat3(m) != glm::dmat3(1.0)) {
        const bool had = !fresh && img.occluders[img.aux[i]].matrix != ~0u;
        ref.matrix = had ? img.occluders[img.aux[i]].matrix : uint32_t(img.occluderMatrices.size());
        if (had)
            img.occluderMatrices[ref.matrix] = m;
        else
            img.occluderMatrices.push_back(m);
    }
    img.aux[i] = slot(img.occluders, i, ref);
    occludersWritten = true;
}

// Prototype p's image, built when missing, or changed and not yet rebuilt in this update: the scene's, or in a
// detail, this image's (NestedImages.cpp builds it).
inline const FlatImage& Scene::Builder::proto(Node* p) {
    auto& slot = (detail ? img.prototypes : scene.protos_)[p];
    if (!slot || (!builtProtos.count(p) && p->dirtyBits())) buildProto(slot, p);
    builtProtos.insert(p);
    return *slot;
}

}  // namespace sg
