// OcclusionPass: the cull's occlusion culling: each frame's OcclusionTree grown from the image's nearest
// large occluders (or its OcclusionMap from the largest on screen), the test of an entry's bound against
// it, and the Adaptive mode's back-off.
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/CullSettings.h"
#include "sg/cull/CullStats.h"
#include "sg/cull/ObbTree.h"
#include "sg/cull/OcclusionMap.h"
#include "sg/cull/OcclusionTree.h"
#include "sg/scene/FlatImage.h"

#include <vector>

namespace sg {

class OcclusionPass {
public:
    // Grows this frame's tree from img's occluders; returns the node where the walk's tests start, or
    // OcclusionTree::kVisible when there is nothing to test against: no occluders, the pass off, the
    // reference render (CullStrategy::None), an orthographic camera, or Adaptive mode skipping this frame.
    int32_t build(const FlatImage& img, const Camera& cam, const CullSettings& set, CullStats& stats);

    // False when entry i of `img` is occluded; otherwise `occ` becomes the node where the tests of the
    // entries below it start. `originRel`: the image's origin relative to the eye. `toEye`: a Geometry
    // entry's frame relative to the eye (its mesh's oriented boxes are tested with it), or null.
    bool test(const FlatImage& img, const dvec3& originRel, uint32_t i, int32_t& occ, CullStats& stats,
              const dmat4* toEye = nullptr);

    // After the walk: the tests' time and box splits into `stats`; in Adaptive mode, whether the frame paid.
    void finish(const OcclusionSettings& s, CullStats& stats);

    // Adaptive mode: a frame where the pass removed `gain` (a share of the walk) below `minGain` did not pay,
    // and the pass skips the next 4, 8, ... up to 64 frames (doubling while it keeps not paying); a frame
    // that paid makes it run every frame again.
    void recordGain(double gain, double minGain);
    int framesToSkip() const { return skipLeft_; }
    // The back-off starts over and the next frame runs the pass: the scene changed (a node moved), or the
    // eye moved more than a quarter of its distance to the nearest occluder when the pass last ran (the
    // eye leaving a building would otherwise see the whole site for up to 64 frames before occlusion
    // comes back).
    void wake() { skipLeft_ = backoff_ = 0; }

    const OcclusionTree& tree() const { return tree_; }
    const OcclusionMap& map() const { return map_; }

private:
    struct Candidate {
        double dist;  // the tree: eye to the box; the map: minus the solid angle over the distance
        uint32_t index;
        double order;          // the tree: the distance over the bound's radius squared (smallest first)
        const FlatImage* img;  // the image whose occluder `index` it is: the scene's or a paged detail's
    };
    // Adds the chosen occluders to the tree (nearest first) or the map (largest solid angle over
    // distance first); returns how many added something.
    uint64_t addToTree(const Camera& cam, const OcclusionSettings& os);
    uint64_t addToMap(const Camera& cam, const OcclusionSettings& os);
    // OcclusionMethod::Auto, after addToTree: whether more than `share` of the next nearest candidates (those
    // the tree could not take, the ones the map would add) are not hidden by the tree.
    bool treeLeavesOccludersVisible(const dvec3& eye, double share);

    OcclusionTree tree_;
    OcclusionMap map_;
    // True when every box of `tree` below node n, down `levels` levels, is hidden in the map.
    bool obbHidden(const ObbTree& tree, uint32_t n, const dmat4& toEye, int levels) const;

    bool hom_ = false;  // this frame's tests go to the map
    int obbLevels_ = 0;
    ObbTree::Cache obbs_;
    std::vector<Candidate> cands_;
    std::vector<const FlatImage*> images_;  // build(): the scene's image and the details drawn, whose occluders count
    std::vector<dvec3> polyScratch_;
    size_t treeStop_ = 0, treeKept_ = 0;  // addToTree: where it stopped in cands_, how far they are sorted
    int skipLeft_ = 0;                    // frames left to skip the pass
    int backoff_ = 0;                     // and how many to skip after the next frame where it does not pay
    dvec3 ranEye_{0.0};                   // the eye when the pass last ran
    double ranNear_ = -1.0;               // and its distance to the nearest candidate then (-1: none)
    double testMs_ = 0.0;                 // this frame's tests
};

}  // namespace sg
