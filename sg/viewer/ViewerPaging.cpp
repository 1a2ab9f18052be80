// Viewer's paging: its pager, the pager stage with the handshake that uploads the pager's details on the draw
// thread, and the look-ahead that carries each view's camera ahead for the pager.
#include "sg/viewer/Viewer.h"
#include "sg/viewer/internal/FramePacket.h"

#include <algorithm>

namespace sg {

Pager& Viewer::enablePaging(PageLoadFunction load, PagerSettings settings) {
    pager_ = nullptr;
    ownPager_.reset();                                    // the old one's thread stops first
    if (keepingFreed_) settings.trimFreedMemory = false;  // the rasterizer's frames keep the memory they free
    ownPager_ = std::make_unique<Pager>(*scene_, std::move(load), settings);
    pager_ = ownPager_.get();
    return *pager_;
}

void Viewer::usePager(Pager* pager) {
    if (pager != ownPager_.get()) ownPager_.reset();
    pager_ = pager;
}

// The pager's update, on the application thread in the update stage.
void Viewer::pagerStage(Packet& p) {
    if (!pager_) return;
    // A pager without a prepare function of its own has its details uploaded by the renderer within the
    // pager's budget before they are attached (Renderer::prepare), for this update only: the pager may
    // outlive the viewer. Only where the renderer's context is current here (SingleThreaded): with a draw
    // thread, a detail is uploaded at its first draw.
    const bool wire = !pager_->prepare();
    if (wire && !threaded_)
        pager_->setPrepare([r = renderer_](Node& d, PrepareBudget& b) { return r->prepare(d, b); },
                           [r = renderer_](const Node& d) { r->forgetPrepare(d); });
    else if (wire)
        pager_->setPrepare([this](Node& d, PrepareBudget& b) { return prepareOnDraw(d, b); },
                           [this](const Node& d) { dropOnDraw(d); });
    try {
        pager_->update(p.info);
    } catch (...) {
        if (wire) pager_->setPrepare({});
        fail("pager", p.info.frame);
        throw;
    }
    if (wire) pager_->setPrepare({});
}

// The view's camera observed, and carried ahead for the look-ahead cull (CullControls::prefetchOnly: frustum and
// LOD ranges only, nothing drawn) when the view asks for one, the viewer has a pager with room in its byte budget,
// and the camera moves.
void Viewer::lookAhead(Packet& p, size_t k) {
    Packet::ViewFrame& vf = p.views[k];
    View& v = *vf.view;
    v.motion_.observe(vf.camera, p.info.time);
    vf.ahead.reset();
    if (!(v.prefetchSeconds > 0.0) || !pager_ || pager_->stats().overBudget) return;
    vf.ahead = v.motion_.predict(vf.camera, v.prefetchSeconds);
}

bool Viewer::prepareOnDraw(Node& detail, PrepareBudget& budget) {
    if (uploaded_.erase(&detail)) return true;
    if (uploadPending_.insert(&detail).second) uploadAsked_.emplace_back(&detail);
    uploadBudget_ = PrepareBudget(budget.ms, budget.objects);
    return false;
}

void Viewer::dropOnDraw(const Node& detail) {
    uploaded_.erase(&detail);
    if (!uploadPending_.erase(&detail)) return;
    const auto asked = std::find_if(uploadAsked_.begin(), uploadAsked_.end(),
                                    [&](const ref_ptr<Node>& d) { return d.get() == &detail; });
    if (asked != uploadAsked_.end())
        uploadAsked_.erase(asked);
    else
        uploadForget_.emplace_back(&detail);  // sent: the renderer may hold a list for it
}

// What the draw thread uploaded becomes the pager's "done"; what it did not is asked again with the next frame.
void Viewer::settleUploads(Packet& p, bool drawn) {
    for (size_t k = 0; k < p.upload.size(); ++k) {
        const Node* d = p.upload[k].get();
        if (!uploadPending_.count(d)) continue;  // dropped meanwhile
        if (drawn && p.uploadDone[k]) {
            uploadPending_.erase(d);
            uploaded_.insert(d);
        } else {
            uploadAsked_.push_back(p.upload[k]);
        }
    }
    p.upload.clear();
    p.forget.clear();
}

}  // namespace sg
