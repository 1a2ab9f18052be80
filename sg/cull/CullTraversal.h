// CullTraversal: walks a Scene's flat image with a Camera and fills a DrawList (frustum tests with plane
// masks and subtree skips, LOD, Switch, Billboard, Instance placements, BspGroup order).
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/CullSettings.h"
#include "sg/cull/DrawList.h"
#include "sg/cull/OcclusionTree.h"
#include "sg/lod/LodSelector.h"
#include "sg/scene/Scene.h"

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
    const OcclusionTree& occlusionTree() const { return otree_; }

private:
    struct Ctx;
    // `occ`: the occlusion tree node where this entry's test starts; OcclusionTree::kVisible: no test.
    void visit(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void children(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    void inside(Ctx& c, uint32_t begin, uint32_t end, const dmat4& m);
    void wideChildren(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ);
    double lodValue(const Ctx& c, uint32_t i) const;
    void fadedLod(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ, double value, float width);
    bool test(Ctx& c, uint32_t i, uint32_t& mask);
    int32_t buildOcclusion(const FlatImage& img);
    bool occlusionTest(const FlatImage& img, const dvec3& originRel, uint32_t i, int32_t& occ);
    void planLods(const FlatImage& img);  // LOD budget: fills chosen_ for deferred_
    // An LOD's header (count of children) followed by one entry per child.
    union LodWork {
        uint32_t count;
        struct Child {
            float tris, items, detail;
        } child;
    };
    uint32_t lodWork(const FlatImage& img, uint32_t i);  // its header's index in lodWork_
    void visitInstance(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m);
    void emit(Ctx& c, uint32_t i, const dmat4& m);
    void setupCtx(Ctx& c, const FlatImage& img, const dmat4& imgToEye);

    const Scene* scene_ = nullptr;
    const Camera* cam_ = nullptr;
    const CullSettings* set_ = nullptr;
    DrawList* out_ = nullptr;
    CullStats* stats_ = nullptr;
    std::vector<uint8_t> cls_;       // batch classifications, used as a stack
    std::vector<uint32_t> scratch_;  // BspGroup orders, used as a stack
    struct Frame {
        uint32_t end;  // entries before this index use m
        dmat4 m;
    };
    std::vector<Frame> frames_;  // transform frames of inside(), a stack up to framesTop_
    size_t framesTop_ = 0;
    uint64_t triangles_ = 0;
    float fade_ = 1.0f;  // the dissolve of what is emitted now (DrawList::fades), 1: none
    OcclusionTree otree_;
    struct Candidate {
        double dist;
        uint32_t index;
    };
    std::vector<Candidate> cands_;
    std::vector<dvec3> polyScratch_;
    int autoWait_ = 0;     // Auto mode: frames left to skip the pass
    int autoBackoff_ = 0;  // and how many to skip after the next frame where it does not pay
    double occlusionTestMs_ = 0.0;
    // LOD hysteresis: the child each LOD entry of the main image showed last (0xff: none).
    std::vector<uint8_t> lodLast_;
    const FlatImage* lodImage_ = nullptr;  // the image lodLast_ is for, and its version
    uint64_t lodVersion_ = 0;
    // LOD budget: the visible LODs met by the walk, planned together once it is done.
    struct DeferredLod {
        uint32_t entry, mask;
        int32_t occ;
        dmat4 m;
    };
    bool planning_ = false;
    std::vector<DeferredLod> deferred_;
    std::vector<int> chosen_;      // per deferred LOD: the child shown, -1: none
    std::vector<double> lodArea_;  // per deferred LOD: its projected area, pixels
    std::vector<LodWork> lodWork_;
    std::vector<uint32_t> lodWorkAt_;  // per image entry: its LodWork header, ~0u: not worked out yet
    std::vector<uint32_t> lodWorkOf_;  // per deferred LOD: its LodWork header
    const FlatImage* lodWorkImage_ = nullptr;
    uint64_t lodWorkVersion_ = 0;
    std::vector<LodSelector::Option> lodOptions_;
    std::vector<LodSelector::Object> lodObjects_;
    LodSelector selector_;
};

}  // namespace sg
