// What the cull does (strategy, small-feature threshold, traversal mask) and what it counted.
#pragma once
#include <cstdint>
#include <string>

namespace sg {

enum class CullStrategy : uint8_t {
    None,          // no frustum tests (the accuracy reference)
    Sphere,        // bounding sphere against the planes
    Aabb,          // box against the planes (nearest/farthest vertex): the default, see below
    SphereSphere,  // the frustum's bounding sphere as a coarse pre-test, then the planes
    CenterBox,     // objects' centres against the frustum's bounding box: cheap, NOT conservative
};
const char* strategyName(CullStrategy s);
// Throws std::invalid_argument listing the valid names.
CullStrategy parseStrategy(const std::string& name);
bool isConservative(CullStrategy s);

struct CullSettings {
    // Boxes: as fast as spheres on `city` (fewer instructions per frame under callgrind, since fewer
    // geometries pass and get sorted; within timing noise otherwise) and tighter, as tight as
    // OpenSceneGraph's per-drawable box test. bench/strategies.sh measures them all.
    CullStrategy strategy = CullStrategy::Aabb;
    double smallFeaturePixels = 0.0;  // drop bounds smaller than this many pixels across; 0: off
    uint32_t traversalMask = 0xffffffffu;
    bool sort = true;  // sort the draw list by state, then front to back
};

struct CullStats {
    uint64_t nodesVisited = 0;
    uint64_t boundsTested = 0;
    uint64_t kernelEntries = 0;  // bounds classified by the flat kernel (straddling subtrees)
    uint64_t culledFrustum = 0;       // by the plane tests
    uint64_t culledSphereSphere = 0;  // by the frustum-sphere pre-test
    uint64_t culledCenterBox = 0;
    uint64_t culledSmallFeature = 0;
    uint64_t instancesVisited = 0;
    uint64_t geometries = 0;
    uint64_t triangles = 0;
    uint64_t invalidDrawn = 0;  // geometries with a NaN/infinite bound, drawn because never culled
    double ms = 0.0;
};

}  // namespace sg
