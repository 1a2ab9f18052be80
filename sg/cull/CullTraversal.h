// CullTraversal: walks a Scene's flat image with a Camera and fills a DrawList (frustum tests with plane
// masks and subtree skips, LOD, Switch, Billboard, Instance placements, BspGroup order).
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/CullSettings.h"
#include "sg/cull/DrawList.h"
#include "sg/cull/LodBudgetPlanner.h"
#include "sg/cull/LodHistory.h"
#include "sg/cull/OcclusionPass.h"
#include "sg/cull/TriangleClusters.h"
#include "sg/scene/Scene.h"

#include <unordered_map>
#include <vector>

namespace sg {

class CullTraversal {
public:
    // A bound that straddles the frustum and has at most this many entries below has them classified by
    // one flat kernel call (vectorized); above that the walk tests one bound at a time.
    static constexpr uint32_t kBatch = 1024;

    // Throws std::logic_error when the scene changed since its last update() (the image would be stale).
    void cull(const Scene& scene, const Camera& camera, const CullSettings& settings, DrawList& out, CullStats& stats);

    // This frame's occlusion tree (empty when the pass did not run). The traversal also keeps the Auto
    // mode's state from frame to frame: use one traversal per view.
    const OcclusionTree& occlusionTree() const { return occlusion_.tree(); }

private:
    struct Ctx;
    // `occ`: the occlusion tree node where this entry's test starts; OcclusionTree::kVisible: no test.
    void visit(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void children(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void inside(Ctx& c, uint32_t begin, uint32_t end, const dmat4& m);
    void wideChildren(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    double lodValue(const Ctx& c, uint32_t i) const;
    void pagedLod(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void fadedLod(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ, double value, float width);
    bool test(Ctx& c, uint32_t i, uint32_t& mask);
    void visitInstance(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m);
    // Sets LOD entry i of c's image aside for the budget's plan.
    void defer(Ctx& c, uint32_t i, uint32_t mask, int32_t occ, const dmat4& m);
    // `inside`: the entry's bound is known inside the frustum (no screen-rectangle test to run).
    void emit(Ctx& c, uint32_t i, const dmat4& m, bool inside);
    void emitTrimmed(Ctx& c, uint32_t i, const dmat4& m);
    void setupCtx(Ctx& c, const FlatImage& img, const dmat4& imgToEye);

    const Scene* scene_ = nullptr;
    const Camera* cam_ = nullptr;
    const CullSettings* set_ = nullptr;
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
    size_t framesTop_ = 0;
    uint64_t triangles_ = 0;
    float fade_ = 1.0f;      // the dissolve of what is emitted now (DrawList::fades), 1: none
    bool planning_ = false;  // the walk sets the visible LODs aside for planner_
    OcclusionPass occlusion_;
    const Scene* occlusionScene_ = nullptr;  // the scene and version the occlusion pass's back-off saw
    uint64_t occlusionVersion_ = 0;
    LodHistory lodHistory_;  // the main image's LODs (hysteresis, budget)
    LodBudgetPlanner planner_;
    // The budget's images this frame (the scene's, prototypes' at each placement) and each one's placement
    // key; a prototype's LODs' last children by placement and entry (last frame's, this frame's).
    std::vector<LodBudgetPlanner::Place> places_;
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
