#include "sg/scene/Scene.h"

#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/scene/internal/BspBuilder.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <tuple>
#include <unordered_set>

namespace sg {

struct Scene::Builder {
    Scene& scene;
    FlatImage& img;
    // Prototypes (re)built in this update in the table proto() fills: one set per table, as a prototype rebuilt in
    // one table (the scene's, a detail's) is still stale in another.
    std::unordered_set<const Node*>& builtProtos;
    uint32_t cursor = 0;
    bool collect = false;    // full builds list the nodes with update callbacks
    bool fresh = false;      // full build: tables are appended to; refit: rewritten at their index
    bool prototype = false;  // building an Instance prototype's image: its occluders are not used
    // Building a PagedLOD detail's image, or a prototype's inside one: not a rebuild of the scene's structure, and
    // the prototypes' images it places are the image's own (img.prototypes), not the scene's, so that the detail
    // can be built alone (buildDetailImage) and its prototypes' images die with it.
    bool detail = false;
    int conditional = 0;  // Switch, LOD, Billboard or masked nodes above: drawn or not per frame
    bool occludersWritten = false;
    // write(): the child written before the current one, and its entry (Occluder::shownWith).
    const Node* prevSibling = nullptr;
    uint32_t prevSiblingEntry = ~0u;
    // What an occluder (or a PagedLOD) below the path being written needs to be drawn, for the pass to check per
    // frame: the Switch children on it (their bytes in switchOn) on, the masked nodes on it (their entries,
    // kMaskCondition set) seen by the traversal mask, the PagedLODs on it (their entries, kPagedCondition set) showing
    // their coarse children. `described` counts the conditional nodes so described: an occluder below an LOD or
    // Billboard (`conditional` counts those too) is not used.
    std::vector<uint32_t> pathConds;
    int described = 0;
    // Pushes the conditions of going from n (entry i) to its child k; returns how many it pushed.
    int enter(uint32_t i, const Node* n, size_t k) {
        const NodeKind kind = n->kind();
        if (kind == NodeKind::LOD || kind == NodeKind::Billboard) return 0;
        int pushed = 0;
        if (kind == NodeKind::Switch) pathConds.push_back(img.aux[i] + uint32_t(k)), pushed++;
        if (kind == NodeKind::PagedLOD) pathConds.push_back(FlatImage::kPagedCondition | i), pushed++;
        if (n->nodeMask() != 0xffffffffu) pathConds.push_back(FlatImage::kMaskCondition | i), pushed++;
        described += isConditional(n);
        return pushed;
    }
    void leave(const Node* n, int pushed) {
        const NodeKind kind = n->kind();
        if (kind == NodeKind::LOD || kind == NodeKind::Billboard) return;
        pathConds.resize(pathConds.size() - size_t(pushed));
        described -= isConditional(n);
    }
    // pathConds stored for an entry that listed `count` of them from `first` before (a full build: none): kept where
    // they are when the same, else appended (a node masked since makes them differ: the old list is left until the
    // next full build).
    std::pair<uint32_t, uint32_t> storeConds(uint32_t first, uint32_t count, bool had) {
        if (had && count == pathConds.size() &&
            std::equal(pathConds.begin(), pathConds.end(), img.occluderSwitchBits.begin() + first))
            return {first, count};
        const auto at = uint32_t(img.occluderSwitchBits.size());
        img.occluderSwitchBits.insert(img.occluderSwitchBits.end(), pathConds.begin(), pathConds.end());
        return {at, uint32_t(pathConds.size())};
    }
    bool underPaged() const {
        return std::any_of(pathConds.begin(), pathConds.end(), [](uint32_t c) {
            return (c & (FlatImage::kPagedCondition | FlatImage::kMaskCondition)) == FlatImage::kPagedCondition;
        });
    }

    static bool isConditional(const Node* n) {
        const NodeKind k = n->kind();
        return k == NodeKind::Switch || k == NodeKind::LOD || k == NodeKind::PagedLOD || k == NodeKind::Billboard ||
               n->nodeMask() != 0xffffffffu;
    }

    struct Counts {
        uint32_t entries = 0, xforms = 0, lods = 0;
    };
    static void count(const Node* n, Counts& c) {
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
    // A PagedLOD's attached detail, which is not among its entry's children (it has an image of its own).
    static const Node* detailOf(const Node* n) {
        return n->kind() == NodeKind::PagedLOD ? static_cast<const PagedLOD*>(n)->detail() : nullptr;
    }

    // A point inside the scene, found by one descent: float offsets from it stay small.
    static dvec3 pickOrigin(const Node* n) {
        dmat4 m(1.0);
        for (int depth = 0; n && depth < 4096; ++depth) {
            if (n->kind() == NodeKind::Transform) m = static_cast<const Transform*>(n)->apply(m);
            if (n->kind() == NodeKind::Instance) m = m * static_cast<const Instance*>(n)->matrix();
            if (n->kind() == NodeKind::Geometry) {
                const Mesh* mesh = static_cast<const Geometry*>(n)->mesh();
                if (mesh && mesh->validBound() && !mesh->box().empty())
                    return dvec3(m * dvec4(mesh->box().center(), 1));
            }
            n = n->numChildren() ? n->child(0) : nullptr;
        }
        const dvec3 t(m[3]);
        return isFinite(t) ? t : dvec3(0.0);
    }

    // The image of `root` placed by `frame` (the identity, but for a paged detail: its PagedLOD's frame).
    void full(Node* root, const dmat4& frame = dmat4(1.0)) {
        img.origin = dvec3(frame * dvec4(pickOrigin(root), 1.0));
        Counts c;
        count(root, c);
        img.resize(c.entries);
        // The tables are filled in order and rewritten in place by later refits. Translations and LODs get
        // one allocation of the counted size (for translations an upper bound: general matrices go to
        // `matrices`), replacing any larger one a previous build left; the other tables grow as filled.
        img.matrices.clear(), img.switchOn.clear(), img.nodes.clear(), img.masked.clear(), img.placements.clear();
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

    void updateExtent() {
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

    // Prototype p's image, built when missing, or changed and not yet rebuilt in this update: the scene's, or in a
    // detail, this image's. A prototype's image in a detail holds the images of the Instances inside it: a table
    // of its own, rebuilt with it.
    const FlatImage& proto(Node* p) {
        auto& slot = (detail ? img.prototypes : scene.protos_)[p];
        if (!slot || (!builtProtos.count(p) && p->dirtyBits())) {
            if (!slot) slot = std::make_shared<FlatImage>();
            std::unordered_set<const Node*> built;
            Builder b{scene, *slot, detail ? built : builtProtos};
            b.collect = collect;
            b.prototype = true;
            b.detail = detail;
            b.full(p);
            b.occluderChunks();
            scene.stats_.entriesWritten += slot->size();
        }
        builtProtos.insert(p);
        return *slot;
    }

    void leafBound(uint32_t i, const Box& local, bool valid, const dmat4& m) {
        if (!valid) {
            img.setInvalid(i);
            return;
        }
        img.setBound(i, transformBox(m, local), glm::length(local.halfExtent()) * maxScale(m));
    }

    void boundFromChildren(uint32_t i) {
        Box b;
        bool invalid = false;
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) {
            if (img.flags[j] & FlatImage::kInvalid) invalid = true;
            if (img.flags[j] & (FlatImage::kEmpty | FlatImage::kInvalid)) continue;
            b.expand(img.box(j));
        }
        if (invalid) return img.setInvalid(i);
        double rad = 0.0;
        const dvec3 c = b.center();
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j])
            if (!(img.flags[j] & FlatImage::kEmpty)) rad = std::max(rad, glm::length(img.center(j) - c) + img.r[j]);
        img.setBound(i, b, rad);
    }

    // Largest distance of anything below `n` from the origin of the frame `m` maps from.
    static double localRadius(const Node* n, const dmat4& m) {
        switch (n->kind()) {
            case NodeKind::Geometry: {
                const Mesh* mesh = static_cast<const Geometry*>(n)->mesh();
                if (!mesh || mesh->box().empty()) return 0.0;
                if (!mesh->validBound()) return kInf;
                const Box b = transformBox(m, mesh->box());
                return glm::length(glm::max(glm::abs(b.min), glm::abs(b.max)));
            }
            case NodeKind::Transform: {
                double r = 0.0;
                const dmat4 mm = static_cast<const Transform*>(n)->apply(m);
                for (size_t i = 0; i < n->numChildren(); ++i) r = std::max(r, localRadius(n->child(i), mm));
                return r;
            }
            case NodeKind::Instance: {
                const auto* in = static_cast<const Instance*>(n);
                return in->prototype() ? localRadius(in->prototype(), m * in->matrix()) : 0.0;
            }
            default: {
                double r = 0.0;
                for (size_t i = 0; i < n->numChildren(); ++i) r = std::max(r, localRadius(n->child(i), m));
                return r;
            }
        }
    }

    void bsp(uint32_t i, Node* n, const dmat4& m) {
        auto* g = static_cast<BspGroup*>(n);
        const dmat4 inv = glm::inverse(m);
        std::vector<Box> boxes;
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j])
            boxes.push_back(img.flags[j] & (FlatImage::kEmpty | FlatImage::kInvalid) ? Box{}
                                                                                     : transformBox(inv, img.box(j)));
        buildBsp(*g, boxes);
    }

    // The LOD's centre in image coordinates: the user's centre through the frame, or the bound's centre.
    void lodCenter(uint32_t i, const LOD* l, const dmat4& m) {
        FlatImage::Lod& lod = img.lods[img.aux[i]];
        const dvec3 c = l->userCenter() ? dvec3(m * dvec4(l->center(), 1.0)) - img.origin : img.center(i) - img.origin;
        lod.cx = float(c.x);
        lod.cy = float(c.y);
        lod.cz = float(c.z);
    }

    // A PagedLOD after its coarse children: its bound grows by the sphere its detail will take, its centre is
    // placed like an LOD's, then its detail's own image is built (`rebuild`, or when missing or changed) in this
    // image's frame and bounded too. The centre leaves the detail out, so that attaching it never moves the
    // value that decides whether it is wanted.
    void paged(uint32_t i, const PagedLOD* p, const dmat4& m, bool rebuild) {
        if (p->radius() > 0.0 && !(img.flags[i] & FlatImage::kInvalid)) {
            const dvec3 c(m * dvec4(p->center(), 1.0));
            expandBound(i, Box{c - dvec3(p->radius() * maxScale(m)), c + dvec3(p->radius() * maxScale(m))},
                        p->radius() * maxScale(m));
        }
        FlatImage::Paged& pg = img.paged[img.aux[i]];
        const dvec3 c = p->userCenter() ? dvec3(m * dvec4(p->center(), 1.0)) - img.origin : img.center(i) - img.origin;
        pg.lod.cx = float(c.x);
        pg.lod.cy = float(c.y);
        pg.lod.cz = float(c.z);
        pg.lod.reach = float(p->radius() * maxScale(m));
        pg.lod.fade = float(maxScale(m));
        pg.frame = m;
        Node* d = p->detail();
        if (!d) {
            pg.detail.reset();
            return;
        }
        const bool adopted = (rebuild || !pg.detail) && adopt(p, d, m, pg);  // built ahead: nothing to build
        if (!adopted && (rebuild || !pg.detail || d->dirtyBits())) {
            // A detail whose own structure is unchanged (a detail attached or detached deeper down, a bound
            // moved) is refitted in place: rebuilding it would rebuild every detail resident below it, the whole
            // tileset's resident images for an attach at depth.
            const bool refitOnly = !rebuild && pg.detail && !(d->dirtyBits() & Node::kDirtyStructure);
            if (!pg.detail) pg.detail = std::make_shared<FlatImage>();
            std::unordered_set<const Node*> built;  // for the detail's own table of prototypes' images
            Builder b{scene, *pg.detail, built};
            b.detail = true;  // its occluders are used while it is drawn (OcclusionPass)
            if (refitOnly) {
                b.refit(0, d, m);
                b.updateExtent();
            } else {
                b.full(d, m);
            }
            if (b.occludersWritten) b.occluderChunks();
        }
        const FlatImage& di = *pg.detail;
        if (di.size() == 0 || (di.flags[0] & FlatImage::kEmpty)) return;
        if (di.flags[0] & FlatImage::kInvalid) return img.setInvalid(i);
        if (!(img.flags[i] & FlatImage::kInvalid)) expandBound(i, di.box(0), di.r[0]);
    }

    // An image offered for this detail in this frame (offerDetailImage) taken, its draw states made the scene's.
    bool adopt(const PagedLOD* p, const Node* d, const dmat4& m, FlatImage::Paged& pg) {
        auto it = scene.offers_.find(p);
        if (it == scene.offers_.end()) return false;
        Offer o = std::move(it->second);
        scene.offers_.erase(it);
        if (o.detail != d || o.frame != m || !o.image) return false;
        renumber(*o.image);
        pg.detail = std::move(o.image);
        return true;
    }

    // An image built alone made to draw with the scene's states: its draws', its prototypes' images' and its
    // attached details' images', all the way down.
    void renumber(FlatImage& image) {
        for (FlatImage::Draw& draw : image.draws)
            draw.state = scene.states_.emplace(std::make_pair(draw.mesh, draw.material), uint32_t(scene.states_.size()))
                             .first->second;
        for (auto& p : image.prototypes) renumber(*p.second);
        for (FlatImage::Paged& p : image.paged)
            if (p.detail) renumber(*p.detail);
    }

    // Entry i's bound grown to hold a world box and the sphere of radius `r` about that box's centre.
    void expandBound(uint32_t i, const Box& add, double r) {
        const bool empty = img.flags[i] & FlatImage::kEmpty;
        Box b = add;
        if (!empty) b.expand(img.box(i));
        const dvec3 bc = b.center();
        double rad = r + glm::length(add.center() - bc);
        if (!empty) rad = std::max(rad, glm::length(img.center(i) - bc) + img.r[i]);
        img.setBound(i, b, rad);
    }

    static constexpr uint32_t kWideChildren = 16, kWideEntries = 1024;
    // A plain Group with many children over a large subtree: its children's spheres side by side.
    void wide(uint32_t i, Node* n) {
        if (n->kind() != NodeKind::Group || n->numChildren() < kWideChildren || img.end[i] - i <= kWideEntries) return;
        if (fresh) {
            img.aux[i] = uint32_t(img.wides.size() + 1);
            img.wides.push_back({uint32_t(img.wideEntry.size()), uint32_t(n->numChildren())});
            for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) {
                img.wideEntry.push_back(j);
                img.wcx.push_back(0), img.wcy.push_back(0), img.wcz.push_back(0), img.wr.push_back(0);
            }
        }
        const FlatImage::Wide& w = img.wides[img.aux[i] - 1];
        for (uint32_t k = 0; k < w.count; ++k) {
            const uint32_t j = img.wideEntry[w.first + k];
            img.wcx[w.first + k] = img.cx[j];
            img.wcy[w.first + k] = img.cy[j];
            img.wcz[w.first + k] = img.cz[j];
            img.wr[w.first + k] = img.r[j];
        }
    }

    // Copies the parameters the cull reads into the kind's table (appended on a full build).
    // A refit rewrites the entry's slot in place, unless the slot is in another table now (a transform
    // that stopped being a translation): then it takes a new one at the end.
    template <class T>
    uint32_t slot(std::vector<T>& v, uint32_t i, const T& value, bool sameTable = true) {
        if (fresh || !sameTable) {
            v.push_back(value);
            return uint32_t(v.size() - 1);
        }
        v[img.aux[i]] = value;
        return img.aux[i];
    }
    // A matrix in img.matrices for the entry that held slot `had` (kNone: none, or a full build): rewritten in
    // place, else appended.
    uint32_t matrixSlot(uint32_t had, const dmat4& m) {
        if (!fresh && had != FlatImage::kNone) {
            img.matrices[had] = m;
            return had;
        }
        img.matrices.push_back(m);
        return uint32_t(img.matrices.size() - 1);
    }
    // The mask is copied (setNodeMask() marks kDirtyBound, which rewrites the entry): the application may set it
    // again while a cull reads this image.
    void setMasked(uint32_t i, const Node* n) {
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
    void params(uint32_t i, Node* n) {
        switch (n->kind()) {
            case NodeKind::Transform: {
                const auto* t = static_cast<const Transform*>(n);
                const bool wasGeneral = img.flags[i] & FlatImage::kGeneral;
                if (t->matrixPtr()) {  // a copy: the node frees its matrix when set again
                    img.aux[i] = matrixSlot(wasGeneral ? img.aux[i] : FlatImage::kNone, *t->matrixPtr());
                    img.flags[i] |= FlatImage::kGeneral;
                } else {
                    img.aux[i] = slot(img.translations, i, t->translation(), !wasGeneral);
                    img.flags[i] &= ~FlatImage::kGeneral;
                }
                break;
            }
            case NodeKind::Geometry: {
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
                break;
            }
            case NodeKind::LOD: {
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
                img.aux[i] = slot(img.lods, i,
                                  FlatImage::Lod{0.0f, 0.0f, 0.0f, it->second, l->transition(), uint8_t(l->mode()),
                                                 l->hasErrors(), 0.0f});
                break;
            }
            case NodeKind::PagedLOD: {
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
                break;
            }
            case NodeKind::Instance: {  // the prototype's image is filled in by write(), once built
                const dmat4& m = static_cast<const Instance*>(n)->matrix();
                const bool t = isTranslation(m);
                const uint32_t had = fresh ? FlatImage::kNone : img.placements[img.aux[i]].matrix;
                img.aux[i] = slot(img.placements, i,
                                  FlatImage::Placement{n, nullptr, t ? dvec3(m[3]) : dvec3(0.0),
                                                       t ? FlatImage::kNone : matrixSlot(had, m)});
                break;
            }
            case NodeKind::Group:
                if (fresh) img.aux[i] = 0;  // a wide Group's index is kept by refits
                break;
            case NodeKind::Occluder: break;  // written with its frame, in write()
            case NodeKind::Switch: {
                if (fresh) {
                    img.aux[i] = uint32_t(img.switchOn.size());
                    img.switchOn.resize(img.switchOn.size() + n->numChildren());
                }
                switchBits(i, n);
                break;
            }
            default: img.aux[i] = slot(img.nodes, i, n); break;
        }
    }

    // Writes the subtree of `n` at `cursor`; `m` is the world matrix of n's parent frame.
    void write(Node* n, const dmat4& m) {
        const uint32_t i = cursor++;
        img.kind[i] = n->kind();
        img.flags[i] &= fresh ? 0 : FlatImage::kGeneral;  // a refit needs to know the transform's old table
        setMasked(i, n);
        params(i, n);
        scene.stats_.entriesWritten++;
        if (collect && n->updateCallback()) scene.callbacks_.push_back(n);
        switch (n->kind()) {
            case NodeKind::Geometry: {
                const Mesh* mesh = static_cast<Geometry*>(n)->mesh();
                img.end[i] = cursor;
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
    void occluder(uint32_t i, const Node* n, const dmat4& m) {
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

    // Chunk boxes over the active occluders, tested against the frustum before the occluders themselves.
    void occluderChunks() {
        const uint32_t k = FlatImage::kOccluderChunk, n = uint32_t(img.occluders.size());
        img.occluderChunks.assign((n + k - 1) / k, Box{});
        for (uint32_t j = 0; j < n; ++j) {
            const FlatImage::OccluderRef& o = img.occluders[j];
            if (o.active && !(img.flags[o.entry] & (FlatImage::kEmpty | FlatImage::kInvalid)))
                img.occluderChunks[j / k].expand(img.box(o.entry));
        }
    }

    // A billboard turns about its origin: bound it, and everything below it, by a sphere there.
    void billboard(uint32_t i, Node* n, const dmat4& m) {
        if (img.flags[i] & FlatImage::kEmpty) return;
        const double rl = localRadius(n, dmat4(1.0));
        const dvec3 o(m[3]);
        const double rad = rl * maxScale(m);
        for (uint32_t j = i; j < img.end[i]; ++j) {
            if (!std::isfinite(rad)) {
                img.setInvalid(j);
            } else {
                img.setBound(j, Box{o - dvec3(rad), o + dvec3(rad)}, rad);
            }
            if (j > i) img.flags[j] |= FlatImage::kNoTest;
        }
    }

    // Structure unchanged: rewrite only the dirty paths in place.
    void refit(uint32_t i, Node* n, const dmat4& m) {
        if ((n->dirtyBits() & Node::kDirtyBound) || n->kind() == NodeKind::Billboard ||
            n->kind() == NodeKind::Instance) {
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

    // Switch n's on bits into its entry i's slot (the children are the same since its entry was written).
    void switchBits(uint32_t i, const Node* n) {
        const auto* sw = static_cast<const Switch*>(n);
        uint8_t* on = img.switchOn.data() + img.aux[i];
        for (size_t k = 0, c = n->numChildren(); k < c; ++k) on[k] = sw->isOn(k);
    }

    // A Switch turned below n (entry i), with no refit to rewrite its entry: follows the kDirtyChoice marks down,
    // into Instance prototypes' and paged details' images too, and copies the bits of the Switches met. A
    // prototype placed many times is met once per path: the copy is the same each time.
    void choices(uint32_t i, Node* n) {
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

    static void clear(Node* n) {
        if (!n->dirtyBits() && !n->choiceChanged()) return;
        n->clearDirty();
        for (size_t k = 0, c = n->numChildren(); k < c; ++k) clear(n->child(k));
    }
};

Scene::Scene(ref_ptr<Node> root) : root_(std::move(root)) {
    if (!root_) throw std::invalid_argument("Scene::Scene(): root is null");
}

Scene::~Scene() = default;

const FlatImage* Scene::prototypeImage(const Node* p) const {
    auto it = protos_.find(p);
    return it == protos_.end() ? nullptr : it->second.get();
}

const FlatImage* Scene::prototypeImage(const FlatImage& placedIn, const Node* p) const {
    if (!placedIn.prototypes.empty()) {  // the scene's image and its prototypes' hold none: no hash for them
        auto it = placedIn.prototypes.find(p);
        if (it != placedIn.prototypes.end()) return it->second.get();
    }
    return prototypeImage(p);
}

void Scene::update(const FrameInfo& frame) {
    const auto t0 = std::chrono::steady_clock::now();
    stats_ = UpdateStats{};
    updates_++;
    frame_ = frame;
    // Structure first (it also finds the nodes with callbacks), then the callbacks, then their changes.
    if ((root_->dirtyBits() & Node::kDirtyStructure) || main_.size() == 0) refresh();
    for (Node* n : callbacks_) {
        (*n->updateCallback())(*n, frame);
        stats_.callbacksRun++;
    }
    refresh();
    offers_.clear();  // images offered for details this update did not meet
    stats_.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::shared_ptr<FlatImage> Scene::buildDetailImage(Node& detail, const dmat4& frame) {
    Scene alone{ref_ptr<Node>(&detail)};  // its own draw states and stats: the adopting scene renumbers the states
    auto img = std::make_shared<FlatImage>();
    std::unordered_set<const Node*> built;
    Builder b{alone, *img, built};
    b.detail = true;  // its prototypes' images are its own: built here too
    b.full(&detail, frame);
    if (b.occludersWritten) b.occluderChunks();
    return img;
}

void Scene::offerDetailImage(const Node* paged, const Node* detail, const dmat4& frame,
                             std::shared_ptr<FlatImage> image) {
    if (paged && detail && image) offers_[paged] = Offer{detail, frame, std::move(image)};
}

void Scene::refresh() {
    const uint8_t bits = root_->dirtyBits() & (Node::kDirtyBound | Node::kDirtyBelow | Node::kDirtyStructure);
    if (bits || main_.size() == 0) {
        version_++;
        std::unordered_set<const Node*> built;
        Builder b{*this, main_, built};
        if ((bits & Node::kDirtyStructure) || main_.size() == 0) {
            callbacks_.clear();
            protos_.clear();
            b.collect = true;
            b.full(root_.get());
            structureVersion_++;
            // A shared node is met once per path: keep its first place in traversal order.
            std::unordered_set<const Node*> seen;
            callbacks_.erase(std::remove_if(callbacks_.begin(), callbacks_.end(),
                                            [&](const Node* n) { return !seen.insert(n).second; }),
                             callbacks_.end());
        } else {
            b.refit(0, root_.get(), dmat4(1.0));
            b.updateExtent();
        }
        if (b.occludersWritten) b.occluderChunks();
        // A Switch turned beside a refit that did not rewrite it (a full build wrote every switch's bits).
        if (!b.collect && root_->choiceChanged()) b.choices(0, root_.get());
        Builder::clear(root_.get());
    } else if (root_->choiceChanged()) {  // a Switch turned: its bits copied into the image, no refit
        version_++;
        std::unordered_set<const Node*> built;
        Builder b{*this, main_, built};
        b.choices(0, root_.get());
        Builder::clear(root_.get());
    }
}

size_t Scene::bytes() const {
    size_t b = main_.bytes();
    for (auto& p : protos_) b += p.second->bytes();
    return b;
}

}  // namespace sg
