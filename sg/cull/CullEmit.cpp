// The cull's fast path over entries known inside the frustum, and the draw items it and the walk emit.
#include "sg/cull/TriangleClusters.h"
#include "sg/cull/internal/CullContext.h"
#include "sg/scene/internal/ImageWalk.h"

namespace sg {

// Entries [begin, end) inside the frustum (no test left): one forward scan over the pre-order entries
// with a stack of transform frames, instead of a call per entry. Anything unusual goes to visit().
void CullTraversal::inside(Ctx& c, uint32_t begin, uint32_t end, const dmat4& m) {
    const FlatImage& img = *c.img;
    // frames_ is a stack addressed by index; `fr` is refreshed after anything that may grow it.
    const size_t base = framesTop_;
    size_t top = base;
    if (top + 2 >= frames_.size()) frames_.resize(frames_.size() * 2 + 16);
    Frame* fr = frames_.data();
    fr[top] = {end, m};
    uint64_t visited = 0;
    uint32_t j = begin;
    while (j < end) {
        while (j >= fr[top].end) --top;
        if (cull::pvsHides(c.pvsHidden, j)) {
            stats_->culledPvs++;
            j = img.end[j];
            continue;
        }
        const uint8_t fl = img.flags[j];
        const NodeKind kind = img.kind[j];
        // Masked, empty, invalid, below a billboard, or a rarer kind: the general path.
        if ((fl & FlatImage::kSlowPath) || !(kind == NodeKind::Geometry || kind == NodeKind::Group ||
                                             kind == NodeKind::Transform || kind == NodeKind::LOD)) {
            const dmat4 vm = fr[top].m;
            framesTop_ = top + 1;
            visit(c, j, 0u, vm, OcclusionTree::kVisible);
            fr = frames_.data();
            j = img.end[j];
            continue;
        }
        ++visited;
        switch (kind) {
            case NodeKind::Geometry:
                emit(c, j, fr[top].m, true);
                ++j;
                break;
            case NodeKind::Group: ++j; break;  // its children follow
            case NodeKind::Transform:
                if (top + 2 >= frames_.size()) {
                    frames_.resize(frames_.size() * 2);
                    fr = frames_.data();
                }
                fr[top + 1].m = transformed(img, j, fr[top].m);
                fr[top + 1].end = img.end[j];
                ++top;
                ++j;
                break;
            default: {  // LOD: the walk's handler, its usual child (a plain geometry) emitted here
                framesTop_ = top + 1;
                lod(c, j, 0u, OcclusionTree::kVisible, frames_[top].m, [&](uint32_t k) {
                    if (cull::pvsHides(c.pvsHidden, k)) {
                        stats_->culledPvs++;
                    } else if (img.kind[k] == NodeKind::Geometry && !(img.flags[k] & FlatImage::kSlowPath)) {
                        ++visited;
                        emit(c, k, frames_[top].m, true);
                    } else {
                        const dmat4 lm = frames_[top].m;  // inside() may grow frames_
                        inside(c, k, img.end[k], lm);
                    }
                });
                fr = frames_.data();
                j = img.end[j];
                break;
            }
        }
    }
    stats_->nodesVisited += visited;
    framesTop_ = base;
}

// Appends the item of draw `d` placed by `m` (its sort depth: the geometry's origin along the view, from the matrix
// at hand; the bounds stay unread: the order is a drawing heuristic, not a visibility decision), dissolved by the LOD
// fade under way; returns its index.
inline uint32_t CullTraversal::pushItem(const Ctx& c, const FlatImage::Draw& d, const dmat4& m) {
    const dvec3& vd = c.viewDir;
    const float depth = float(vd.x * m[3].x + vd.y * m[3].y + vd.z * m[3].z);
    DrawItem& it = out_->push(d.state, depth);
    it.mesh = d.mesh;
    it.material = d.material;
    toFloat(m, it.model);
    const auto item = uint32_t(out_->items.size() - 1);
    if (fade_ != 1.0f) out_->fades.push_back({item, fade_});
    return item;
}

void CullTraversal::emit(Ctx& c, uint32_t i, const dmat4& m, bool inside) {
    const FlatImage& img = *c.img;
    const FlatImage::Draw& d = img.draws[img.aux[i]];
    if (!d.mesh || prefetchOnly_) return;
    if (img.flags[i] & FlatImage::kPosed) return emitPosed(c, i, m);
    // The rejection's path is its own function: the usual path stays as short as without the option.
    if (screenRect_ && !inside) return emitTrimmed(c, i, m);
    const bool invalid = img.flags[i] & FlatImage::kInvalid;
    pushItem(c, d, m);
    triangles_ += d.mesh->triangleCount();
    points_ += d.mesh->pointCount();
    lines_ += d.mesh->lineCount();
    if (invalid) stats_->invalidDrawn++;
}

// A posed Geometry's item: its own mesh and material (the draw state does not change as it moves), noted with its
// pose. A skinned pose's vertices are in world coordinates less its anchor, whatever the path's matrix: the item's
// matrix is the translation from the eye to the anchor. Never trimmed to the screen: its clusters are the bind pose's.
void CullTraversal::emitPosed(Ctx& c, uint32_t i, const dmat4& m) {
    const FlatImage& img = *c.img;
    const FlatImage::Draw& d = img.draws[img.aux[i]];
    const Pose* pose = img.poseOf(i);
    const dmat4 model = pose && pose->skinned() ? glm::translate(dmat4(1.0), pose->anchor - cam_->eye()) : m;
    const uint32_t item = pushItem(c, d, model);
    if (pose) out_->poses.emplace_back(item, pose);
    triangles_ += d.mesh->triangleCount();
    points_ += d.mesh->pointCount();
    lines_ += d.mesh->lineCount();
    if (img.flags[i] & FlatImage::kInvalid) stats_->invalidDrawn++;
}

// emit() with the screen-rectangle rejection: the clusters off screen are left out, the rest drawn as ranges.
void CullTraversal::emitTrimmed(Ctx& c, uint32_t i, const dmat4& m) {
    const FlatImage& img = *c.img;
    const FlatImage::Draw& d = img.draws[img.aux[i]];
    const uint32_t triangles = d.mesh->triangleCount();
    if ((img.flags[i] & FlatImage::kInvalid) || triangles == 0) return emit(c, i, m, true);
    const TriangleClusters& tc = clusters_.get(*d.mesh, set_->screenRectTriangles);
    std::vector<IndexRange>& ranges = out_->ranges;
    const size_t firstRange = ranges.size();
    const uint32_t kept =
        tc.keepInViewport(viewProj_, m, ranges, stats_->screenRectClusters, stats_->culledScreenRectClusters);
    stats_->culledScreenRectTriangles += triangles - kept;
    if (kept == 0) {
        stats_->culledScreenRectGeometries++;
        ranges.resize(firstRange);
        return;
    }
    if (kept == triangles) {  // every cluster on screen: the whole mesh, batched with its like
        ranges.resize(firstRange);
        return emit(c, i, m, true);
    }
    const uint32_t item = pushItem(c, d, m);
    out_->parts.push_back({item, uint32_t(firstRange), uint32_t(ranges.size() - firstRange), true});
    triangles_ += kept;
}

}  // namespace sg
