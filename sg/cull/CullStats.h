// CullStats: what one cull counted (tests by kind, what each culled, the occlusion pass, the LOD budget, paged
// nodes, the screen-rectangle rejection) and how long it took.
#pragma once
#include "sg/lod/LodPlanStats.h"

#include <cstdint>

namespace sg {

// The LOD budget's figures (lodObjects ... lodSelectMs) are LodPlanStats', which the planner fills in.
struct CullStats : LodPlanStats {
    uint64_t nodesVisited = 0;
    uint64_t boundsTested = 0;
    uint64_t kernelEntries = 0;       // bounds classified by the flat kernel (straddling subtrees)
    uint64_t culledFrustum = 0;       // by the plane tests
    uint64_t culledSphereSphere = 0;  // by the frustum-sphere pre-test
    uint64_t culledCenterBox = 0;
    uint64_t culledSmallFeature = 0;
    uint64_t instancesVisited = 0;
    uint64_t geometries = 0;
    uint64_t triangles = 0;
    uint64_t points = 0, lines = 0;  // points and line segments of the geometries drawn
    uint64_t invalidDrawn = 0;       // geometries with a NaN/infinite bound, drawn because never culled
    // Occlusion pass
    bool occlusionRan = false;        // the pass ran: a tree or a map was built (occluders in view, not skipped)
    bool occlusionSkipped = false;    // Adaptive mode skipped it this frame
    bool occlusionMap = false;        // the pass built the occlusion map, not the tree (OcclusionMethod)
    uint64_t occluderCandidates = 0;  // occluders in view and large enough
    uint64_t occludersUsed = 0;       // added something to the tree
    uint64_t occlusionTreeNodes = 0;
    uint64_t occlusionPolygonSplits = 0;  // occluder polygons split while growing the tree
    uint64_t occlusionBoxSplits = 0;      // bounds split by a tree plane while tested
    uint64_t occlusionTests = 0;
    uint64_t culledOcclusion = 0;  // bounds culled as occluded
    uint64_t culledObb = 0;  // of them, geometries culled by their oriented boxes (OcclusionSettings::homObbLevels)
    uint64_t occludedEntries = 0;  // image entries below them (work the walk skipped)
    double occlusionMs = 0.0;      // growing the tree plus the tests
    // LODs whose history is kept (hysteresis or the budget on) showing another child than last frame, none where
    // they showed one or one where they showed none (not at first sight): the level changes a viewer sees pop. On a
    // still view, flicker.
    uint64_t lodChanged = 0;
    // Paged nodes (PagedLOD)
    uint64_t pagedWanted = 0;     // seen with their detail in range
    uint64_t pagedRequested = 0;  // posted for loading (once per update each)
    uint64_t pagedCoarse = 0;     // wanted but not loaded yet: their coarse level was drawn
    double ms = 0.0;
    uint64_t culledPvs = 0;  // entries culled as hidden from the eye's cell (CullSettings::pvs)
    // Screen-rectangle rejection (CullSettings::screenRect); `triangles` above counts what is left.
    uint64_t screenRectClusters = 0;          // clusters tested
    uint64_t culledScreenRectClusters = 0;    // clusters outside the viewport
    uint64_t culledScreenRectTriangles = 0;   // their triangles
    uint64_t culledScreenRectGeometries = 0;  // geometries every cluster of which was outside (not drawn)
};

}  // namespace sg
