// Occlusion: the state of one run of the occlusion mode, which OcclusionBench.cpp sets up and culls and
// OcclusionReport.cpp prints.
#pragma once
#include <osg/FrameStamp>
#include <osgUtil/SceneView>

#include <cstdint>
#include <vector>

#ifdef SGBENCH_WITH_SGKIT
#include "sg/cull/CullTraversal.h"

#include <memory>
#endif

#include "Bench.h"

namespace osgbench {

// Time stamps that split SceneView::cull: its occluder collection starts with
// CollectOccludersVisitor::reset() and ends right before CullVisitor::reset()
// (removeOccludedOccluders and the hand-over to the CullVisitor included).
struct CullMarks {
    Clock::time_point collectStart, cullStart;
    bool collected = false;
};

// What one cull configuration produced over the timed frames.
struct Series {
    std::vector<double> ms;
    std::vector<double> collectMs;  // OSG: the occluder collection part of ms
    double geometries = 0.0, triangles = 0.0, occluders = 0.0;
};

// One OSG cull configuration: a SceneView of its own, with its own (warm) render graph pools.
struct OsgConfig {
    const char* name;
    osgcity::Scene* scene;
    unsigned mode;
    osg::ref_ptr<osgUtil::SceneView> sv;
    Series s;
    CullMarks marks;
    std::vector<LeafKey> keys;  // this frame's draw leaves (occlusion and frustum-only configs)
};

#ifdef SGBENCH_WITH_SGKIT
// sgkit's cull of its own occluder city: frustum only and frustum + occlusion tree.
struct SgkitOcclusion {
    std::unique_ptr<sg::Scene> scene;
    sg::CullSettings frustum, occlusion;
    sg::CullTraversal cullFrustum, cullOcclusion;  // one per setting, as each keeps per-view state
    sg::DrawList list;
    Series f, o;
};
#endif

// The scenes point at meshes and the configurations at the scenes: a run is never moved.
struct OcclusionRun {
    int frames = 0;
    double zNear = 0.0;
    osgcity::Meshes meshes;
    osgcity::Scene occScene;    // the city with occluders
    osgcity::Scene plainScene;  // the same city without them, sharing every mesh
    double buildSeconds = 0.0;
    osg::ref_ptr<osg::FrameStamp> frameStamp;
    std::vector<OsgConfig> osgConfigs;  // occlusion, frustum, occluders_ignored, in this order
    uint64_t notSubset = 0;             // draw leaves of the occlusion cull that the frustum-only cull did not draw
#ifdef SGBENCH_WITH_SGKIT
    SgkitOcclusion sgkit;
#endif

    OsgConfig& osgOcc() { return osgConfigs[0]; }
    OsgConfig& osgOff() { return osgConfigs[1]; }
    const OsgConfig& osgOcc() const { return osgConfigs[0]; }
    const OsgConfig& osgOff() const { return osgConfigs[1]; }
    const OsgConfig& osgIgn() const { return osgConfigs[2]; }
};

// OcclusionReport.cpp: the run's figures as one JSON object (--json) or as a table, on stdout.
void reportOcclusion(const OcclusionOptions& o, const OcclusionRun& run);

}  // namespace osgbench
