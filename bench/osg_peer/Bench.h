// Bench: what sgbench_osg's benchmarks share (the clock, the statistics, the SceneView set-up, the counting of
// a cull's draw leaves) and the entry point of each benchmark.
#pragma once
#include <osg/FrameStamp>
#include <osg/Node>
#include <osgUtil/RenderStage>
#include <osgUtil/SceneView>

#include <chrono>
#include <cstdint>
#include <tuple>
#include <vector>

#include "OsgCity.h"

namespace osgbench {

using Clock = std::chrono::steady_clock;
inline double msBetween(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// ---------------------------------------------------------------------------
// Statistics (Stats.cpp).

double median(std::vector<double> v);
double percentile95(std::vector<double> v);

// ---------------------------------------------------------------------------
// Options (sgbench_osg.cpp): prints the error and the usage, exits with status 2.

[[noreturn]] void usage(const char* msg);

// ---------------------------------------------------------------------------
// SceneView set-up (CullSetup.cpp).

constexpr unsigned kFrustumCulling = osg::CullSettings::VIEW_FRUSTUM_SIDES_CULLING |
                                     osg::CullSettings::NEAR_PLANE_CULLING | osg::CullSettings::FAR_PLANE_CULLING;

osg::ref_ptr<osgUtil::SceneView> makeSceneView(osg::Node* scene, osg::FrameStamp* frameStamp, double zNear,
                                               unsigned cullingMode);
bool checkInherited(const osgUtil::SceneView& sv, unsigned cullingMode);

// ---------------------------------------------------------------------------
// Verification (DrawCount.cpp): the draw leaves (one RenderLeaf per selected Geometry instance) of the render
// graph a cull produced, and their triangles.

struct DrawCount {
    uint64_t leaves = 0;
    uint64_t triangles = 0;
};

DrawCount countStage(const osgUtil::RenderStage& stage, const osgcity::Scene& scene);

// A draw leaf's identity across two culls of the same frame: the drawable and
// where it is drawn (the translation of its model-view matrix, which both culls
// compute the same way from the same view matrix and transforms).
using LeafKey = std::tuple<const osg::Drawable*, double, double, double>;

std::vector<LeafKey> leafKeys(const osgUtil::RenderStage& stage);

// ---------------------------------------------------------------------------
// The benchmarks, one a mode; each returns the process's exit status.

// CullBench.cpp: the orbit path, frustum culling, the scene without occluders.
int runCull(int n, int passes, bool withSgkit);

struct OcclusionOptions {
    int n = 100;
    int passes = 1;
    bool street = true;
    bool withSgkit = false;
    bool json = false;
    osgcity::OccluderKind occluders = osgcity::OccluderKind::Diagonals;
    unsigned maxOccluders = 10;  // OSG's default (CollectOccludersVisitor)
    double minVolume = 0.005;    // OSG's default (CollectOccludersVisitor)
    double occluderRange = 0.0;  // > 0: occluders only within this distance (an LOD around them)
};

// OcclusionBench.cpp: OSG's shadow-volume occlusion culling beside frustum culling only.
int runOcclusion(const OcclusionOptions& o);

#ifdef SGBENCH_WITH_SGKIT
// PickBench.cpp: the rays of `sgbench pick`, picked by OSG and by sgkit.
int runPick(int n, int raysPerFrame);
#endif

}  // namespace osgbench
