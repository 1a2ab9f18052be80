// CullTraversal: walks a Scene's flat image with a Camera and fills a DrawList (frustum tests with plane
// masks and subtree skips, LOD, Switch, Billboard, Instance placements, BspGroup order).
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/CullSettings.h"
#include "sg/cull/CullStats.h"
#include "sg/cull/DrawList.h"
#include "sg/cull/OcclusionPass.h"
#include "sg/cull/TriangleClusters.h"
#include "sg/lod/LodBudgetPlanner.h"
#include "sg/lod/LodHistory.h"
#include "sg/scene/ImageFrame.h"
#include "sg/scene/Scene.h"

#include <memory>
#include <unordered_map>
#include <vector>

namespace sg {

class LodChooser;
class PvsTable;

// How a frame loop runs a cull, beside what the application set (CullSettings, left as it was set): sg::Viewer's
// controls of its views' culls.
struct CullControls {
    // The application may be changing the graph while this cull runs (a viewer's app stage running beside the
    // cull): cull the image of the scene's last update() without checking that the graph is unchanged since,
    // a check that reads the root node. The cull reads no node state the application writes per frame (switch
    // bits, node masks and matrices are copies in the image), but a node it removes must outlive the cull
    // (sg::DeferredRelease). Off: a scene changed since its update() is refused.
    bool imageOfLastUpdate = false;
    // A cull that only looks ahead for the pager (View::prefetchSeconds): it tests frustum and LOD ranges alone (no
    // occlusion: an occluder may have moved out of the way by then; no PVS, no budget or hysteresis: the plain
    // ranges say what will be wanted there; no screen rectangles), draws nothing (the draw list stays empty), and
    // marks each paged detail this camera would want as needed, asking for it below every request a drawing cull
    // makes (its priority lowered by kPrefetchPriorityDrop), so that what a view will soon need loads in the time
    // the loaders have left, and stays while it is still predicted.
    bool prefetchOnly = false;
};

class CullTraversal {
public:
    // A bound that straddles the frustum and has at most this many entries below has them classified by
    // one flat kernel call (vectorized); above that the walk tests one bound at a time.
    static constexpr uint32_t kBatch = 1024;

    // Throws std::logic_error when the scene changed since its last update() (the image would be stale), unless
    // CullControls::imageOfLastUpdate.
    void cull(const Scene& scene, const Camera& camera, const CullSettings& settings, DrawList& out, CullStats& stats,
              const CullControls& controls = {});

    // This frame's occlusion tree (empty when the pass did not run). The traversal also keeps the Adaptive
    // mode's state from frame to frame: use one traversal per view.
    const OcclusionTree& occlusionTree() const { return occlusion_.tree(); }

private:
    struct Ctx;
    // The walk: visit() runs entry i's tests, then the handler of its kind. `occ`: the occlusion tree node
    // where this entry's test starts; OcclusionTree::kVisible: no occlusion test below (0, the root, is a
    // node like the others: tested against the whole tree, or against the map when the map was built).
    void visit(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void handle(Ctx& c, uint32_t i, uint32_t mask, uint32_t maskIn, const dmat4& m, int32_t occ);
    void featureNode(Ctx& c, uint32_t i, uint32_t mask, uint32_t maskIn, const dmat4& m, int32_t occ);
    bool test(Ctx& c, uint32_t i, uint32_t& mask);  // the bound against the planes
    // The handlers, one per kind (Transform's and Occluder's are a line in visit()).
    void group(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    template <class Walk>
    void lod(Ctx& c, uint32_t i, uint32_t mask, int32_t occ, const dmat4& m, const Walk& walk);
    void switchChildren(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void billboard(Ctx& c, uint32_t i, const dmat4& m);
    void instance(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m);
    void bspGroup(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void pagedLod(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    float pagedPriority(const Ctx& c, uint32_t i) const;  // what pagedLod() posts with a request
    void children(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void wideChildren(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    // Entries [begin, end) known inside the frustum, no occlusion test left: the fast path.
    void inside(Ctx& c, uint32_t begin, uint32_t end, const dmat4& m);
    // Sets LOD entry i of c's image aside for the budget's plan; after the walk, the plan's children walked.
    void defer(Ctx& c, uint32_t i, uint32_t mask, int32_t occ, const dmat4& m);
    void replayBudget(Ctx& sceneCtx, const LodBudgetSettings& lb);
    // `inside`: the entry's bound is known inside the frustum (no screen-rectangle test to run).
    void emit(Ctx& c, uint32_t i, const dmat4& m, bool inside);
    void emitTrimmed(Ctx& c, uint32_t i, const dmat4& m);
    void emitPosed(Ctx& c, uint32_t i, const dmat4& m);
    uint32_t pushItem(const Ctx& c, const FlatImage::Draw& d, const dmat4& m);
    // `planes` false: the walk below tests nothing (its bound is inside the frustum), only the frame is set.
    void setupCtx(Ctx& c, const FlatImage& img, const dmat4& imgToEye, bool planes = true);
    void checkPvs(const Scene& scene, const Camera& cam, const PvsTable& t);

    const Scene* scene_ = nullptr;
    const Camera* cam_ = nullptr;
    const CullSettings* set_ = nullptr;
    bool prefetchOnly_ = false;  // CullControls::prefetchOnly
    DrawList* out_ = nullptr;
    CullStats* stats_ = nullptr;
    std::vector<uint8_t> cls_;  // batch classifications, used as a stack
    // BspGroups being walked, used as a stack: each one's child entries, then its front-to-back order.
    std::vector<uint32_t> scratch_;
    std::vector<uint32_t> bspOrder_;  // BspGroup::order()'s answer, copied to scratch_ at once
    struct Frame {
        uint32_t end;  // entries before this index use m
        dmat4 m;
    };
    std::vector<Frame> frames_;  // transform frames of inside(), a stack up to framesTop_
    // Contexts of the Instance placements being walked, by depth: made once, not zeroed per placement (a
    // context is most of a placement's cost in a tile of thousands).
    std::vector<std::shared_ptr<Ctx>> placementCtx_;
    size_t placementDepth_ = 0;
    size_t framesTop_ = 0;
    uint64_t triangles_ = 0, points_ = 0, lines_ = 0;
    float fade_ = 1.0f;      // the dissolve of what is emitted now (DrawList::fades), 1: none
    bool planning_ = false;  // the walk sets the visible LODs aside for planner_
    OcclusionPass occlusion_;
    const Scene* occlusionScene_ = nullptr;  // the scene and version the occlusion pass's back-off saw
    uint64_t occlusionVersion_ = 0;
    const LodChooser* chooser_ = nullptr;  // this frame's LOD rules (sg/lod/internal/LodChooser.h)
    bool lodTracked_ = false;              // the scene's LODs remember what they showed (hysteresis)
    LodHistory lodHistory_;                // the main image's LODs (hysteresis, budget)
    LodBudgetPlanner planner_;
    // The budget's images this frame (the scene's, prototypes' at each placement) and each one's placement
    // key; a prototype's LODs' LodHistory records by placement and entry (last frame's, this frame's).
    std::vector<ImageFrame> places_;
    std::vector<uint64_t> placeKey_;
    std::unordered_map<uint64_t, uint8_t> protoLast_, protoShown_;
    // Screen-rectangle rejection (CullSettings::screenRect): on this frame, and its clusters by mesh.
    bool screenRect_ = false;
    dmat4 viewProj_{1.0};
    TriangleClusters::Cache clusters_;
    // The PVS table last found to match the scene (its address and hash), at that scene's version and size:
    // checked again when any of them changes.
    const void* pvsChecked_ = nullptr;
    uint64_t pvsHash_ = 0;
    const Scene* pvsScene_ = nullptr;
    uint64_t pvsVersion_ = 0;
    size_t pvsEntries_ = 0;
};

}  // namespace sg
