// The images an image holds, built by a Builder of their own: an Instance prototype's (once however often it is
// placed) and a PagedLOD detail's (built here, or built ahead off the frame thread and adopted).
#include "sg/scene/internal/ImageBuilder.h"

#include <memory>
#include <unordered_set>
#include <utility>

namespace sg {

// Prototype p's image (re)built into `slot`, the scene's table's or, in a detail, this image's. A prototype's
// image in a detail holds the images of the Instances inside it: a table of its own, rebuilt with it.
void Scene::Builder::buildProto(std::shared_ptr<FlatImage>& slot, Node* p) {
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

// PagedLOD p's detail d's image in the frame m, adopted when offered (if `rebuild` or missing), else built: whole
// (`rebuild`, missing, or its structure changed), or refitted in place.
void Scene::Builder::detailImage(const PagedLOD* p, Node* d, const dmat4& m, FlatImage::Paged& pg, bool rebuild) {
    if ((rebuild || !pg.detail) && adopt(p, d, m, pg)) return;  // built ahead: nothing to build
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

// An image offered for this detail in this frame (offerDetailImage) taken, its draw states made the scene's.
bool Scene::Builder::adopt(const PagedLOD* p, const Node* d, const dmat4& m, FlatImage::Paged& pg) {
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
void Scene::Builder::renumber(FlatImage& image) {
    for (FlatImage::Draw& draw : image.draws)
        draw.state = scene.states_.emplace(std::make_pair(draw.mesh, draw.material), uint32_t(scene.states_.size()))
                         .first->second;
    for (auto& p : image.prototypes) renumber(*p.second);
    for (FlatImage::Paged& p : image.paged)
        if (p.detail) renumber(*p.detail);
}

}  // namespace sg
