// DrawCount: walks the render graph a cull produced, outside the timed region, to verify what it selected.
#include <osgUtil/RenderBin>
#include <osgUtil/RenderLeaf>
#include <osgUtil/RenderStage>
#include <osgUtil/StateGraph>

#include <algorithm>

#include "Bench.h"

namespace osgbench {

namespace {

template <class F>
void forEachLeafInBin(const osgUtil::RenderBin& bin, const F& f) {
    // State-sorted bins keep leaves in their StateGraphs; depth-sorted bins
    // move them to the RenderLeafList. A leaf is in exactly one of the two.
    for (const osgUtil::StateGraph* sg : bin.getStateGraphList())
        for (const auto& leaf : sg->_leaves) f(leaf.get());
    for (const osgUtil::RenderLeaf* leaf : bin.getRenderLeafList()) f(leaf);
    for (const auto& child : bin.getRenderBinList()) forEachLeafInBin(*child.second, f);
}

template <class F>
void forEachLeaf(const osgUtil::RenderStage& stage, const F& f) {
    for (const auto& pre : stage.getPreRenderList()) forEachLeafInBin(*pre.second, f);
    forEachLeafInBin(stage, f);
    for (const auto& post : stage.getPostRenderList()) forEachLeafInBin(*post.second, f);
}

}  // namespace

DrawCount countStage(const osgUtil::RenderStage& stage, const osgcity::Scene& scene) {
    DrawCount out;
    forEachLeaf(stage, [&](const osgUtil::RenderLeaf* leaf) {
        ++out.leaves;
        auto it = scene.meshes->triangles.find(leaf->getDrawable());
        if (it != scene.meshes->triangles.end()) out.triangles += it->second;
    });
    return out;
}

std::vector<LeafKey> leafKeys(const osgUtil::RenderStage& stage) {
    std::vector<LeafKey> keys;
    forEachLeaf(stage, [&](const osgUtil::RenderLeaf* leaf) {
        const osg::RefMatrix* mv = leaf->_modelview.get();
        keys.emplace_back(leaf->getDrawable(), mv ? (*mv)(3, 0) : 0.0, mv ? (*mv)(3, 1) : 0.0, mv ? (*mv)(3, 2) : 0.0);
    });
    std::sort(keys.begin(), keys.end());
    return keys;
}

}  // namespace osgbench
