// What the cull does (strategy, small-feature threshold, traversal mask) and what it counted.
#pragma once
#include "sg/core/Settings.h"
#include "sg/lod/LodBudgetSettings.h"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace sg {

enum class CullStrategy : uint8_t {
    None,          // no culling of any kind, occlusion included (the accuracy reference)
    Sphere,        // bounding sphere against the planes
    Aabb,          // box against the planes (nearest/farthest vertex): the default, see below
    SphereSphere,  // the frustum's bounding sphere as a coarse pre-test, then the planes
    CenterBox,     // objects' centres against the frustum's bounding box: cheap, NOT conservative
};
const char* strategyName(CullStrategy s);
// Throws std::invalid_argument listing the valid names.
CullStrategy parseStrategy(const std::string& name);
bool isConservative(CullStrategy s);

// When the occlusion pass runs (what it builds is OcclusionMethod): major occluders fused into one tree or map
// per frame; bounds inside the occluded space are culled.
enum class OcclusionMode : uint8_t {
    Off,
    EveryFrame,  // every frame that has occluders in view
    Adaptive,    // EveryFrame, but skipped for a while after frames where it culled too little to pay (aerial views)
};
enum class OccluderCap : uint8_t {
    FrontFaces,   // a box occludes behind its front faces: conservative (the default)
    CenterPlane,  // the paper's plane through the box centre, facing the eye: NOT conservative (grazing rays)
};
// What the pass builds each frame to test bounds against.
enum class OcclusionMethod : uint8_t {
    Tree,  // the occlusion tree (sg/cull/OcclusionTree.h): exact shadow volumes of the occluders, fused
    Hom,   // a hierarchical occlusion map (sg/cull/OcclusionMap.h): occluders rasterized into a coverage
           // pyramid and a depth buffer; cheaper to build, and approximate when homOpacity is below 1
    // Per frame: the tree is built, then tested with the next nearest occluders it could not take; when more
    // than autoMapShare of those still show (many scattered occluders, as over a city's lower roofs), the map
    // is built instead, which takes four times as many and fuses them; when the tree hides them (rooms,
    // walls, streets), the tree is kept: exact and cheapest there. Both are conservative (docs/benchmarks.md,
    // "Run time against error": the choice measured per scene). The default.
    Auto,
};
const char* occlusionModeName(OcclusionMode m);
const char* occlusionMethodName(OcclusionMethod m);
// Throws std::invalid_argument listing the valid names ("tree", "hom", "auto").
OcclusionMethod parseOcclusionMethod(const std::string& name);
// Throws std::invalid_argument listing the valid names ("off", "every-frame", "adaptive"; the older "tree"
// and "auto" are still taken).
OcclusionMode parseOcclusionMode(const std::string& name);

struct OcclusionSettings {
    OcclusionMode mode = OcclusionMode::Adaptive;  // when the pass runs
    OcclusionMethod method = OcclusionMethod::Auto;
    // OcclusionMethod::Auto: the share of the next nearest occluders left showing by the tree above which the map is
    // used, in [0, 1]: the map where scattered occluders stay visible past the tree's (docs/benchmarks.md, "Run time
    // against error", has the share measured per scene).
    double autoMapShare = 0.15;
    uint32_t maxOccluders = 16;       // occluders added to the tree per frame (hidden ones do not count)
    double minOccluderPixels = 24.0;  // occluders smaller than this across on screen are not used; >= 0
    double adaptiveMinGain = 0.1;     // Adaptive: a frame "pays" when occlusion removed this share of the entries
    // Hom: the map's size in pixels over the viewport (powers of two, 8 to 1024), and the opacity at which
    // a pyramid pixel counts as covered: 1 is conservative; below 1 a bound seen only through holes that
    // make up less than 1 - homOpacity of some pyramid pixel is culled too (approximate: it has error).
    int homWidth = 256, homHeight = 256;
    double homOpacity = 1.0;
    // Hom: occluders rasterized per frame, largest solid angle over distance first (maxOccluders is the
    // tree's): rasterizing one costs little, so the map takes more than the tree (docs/benchmarks.md).
    uint32_t homMaxOccluders = 64;
    // Hom: a geometry its world box does not show hidden is tested again by the oriented boxes of its
    // mesh's ObbTree (sg/cull/ObbTree.h), tighter on screen, down this many levels below the root (0: off);
    // 0..16.
    int homObbLevels = 0;

    // Switches that exist to measure the papers' refinements against their absence: not options to tune.
    struct MeasureOnly {
        // FrontFaces is conservative; CenterPlane is the paper's cap, NOT conservative (grazing rays miss it).
        OccluderCap cap = OccluderCap::FrontFaces;
        int screenSplits = 0;  // two-level tree: 2^k screen regions above the occluders (0: one level), 0..8
    };
    MeasureOnly measureOnly;

    // Throws SettingError naming `caller`, the setting, its value and the values allowed.
    void validate(const char* caller) const;
};

class PvsTable;

// How far a look-ahead cull's requests rank below a drawing cull's (CullControls::prefetchOnly): a drawing cull's
// priorities lie in (-depth, 1] (CullTraversal::pagedPriority), depth below this.
constexpr float kPrefetchPriorityDrop = 256.0f;

// CullSettings::MeasureOnly::frustumPlanes without the near, top and bottom planes.
constexpr uint32_t kTerrainPaperPlanes = 0x23;

struct CullSettings {
    // Boxes: as fast as spheres (fewer geometries pass and get sorted) and tighter, as tight as OpenSceneGraph's
    // per-drawable box test. bench/strategies.sh measures them all (docs/benchmarks.md).
    CullStrategy strategy = CullStrategy::Aabb;
    // Drop bounds smaller than this many pixels across (the bound's diameter at its centre's distance); 0:
    // off; >= 0. At 1 it is the terrain paper's screen-radius test r = wR / (2 d tan(theta / 2)) < 1 pixel.
    double smallFeaturePixels = 0.0;
    uint32_t traversalMask = 0xffffffffu;
    bool sort = true;  // sort the draw list by state, then front to back
    // LOD hysteresis: the child an LOD showed last frame stays while the distance (or pixel size) is within
    // its range widened by this fraction at both ends, so an eye hovering at a boundary does not make the
    // level flicker. 0: off (the plain ranges, frame by frame, as OpenSceneGraph and Performer). It needs
    // one CullTraversal per view (the last choices are kept there); applied to the scene's own LODs only, not
    // inside Instance prototypes nor loaded PagedLOD details (they have images of their own).
    // In [0, 1).
    double lodHysteresis = 0.0;
    // LOD distances are multiplied by this (pixel sizes divided): above 1, coarser levels nearer. Performer's
    // and OpenSceneGraph's LOD scale; sg/lod/LodStress.h drives it from the frame time.
    double lodScale = 1.0;
    // LOD fade (LOD::setTransition): children dissolve in and out over their LOD's band. Off: every band is
    // ignored and levels pop at the plain boundaries (as without transitions). Not applied to the LODs the
    // budget plans (lodBudget), which change level only when the budget does.
    bool lodFade = true;
    LodBudgetSettings lodBudget;  // when enabled, LOD ranges, scale and hysteresis are not used
    OcclusionSettings occlusion;
    // From-region visibility (sg/cull/PvsTable.h, built by PvsBuilder): the main image's entries hidden from
    // the eye's cell are culled before any other test. Null: none. Not used by the reference
    // (CullStrategy::None) nor for orthographic cameras; the table must match the scene.
    const PvsTable* pvs = nullptr;
    // PCVR's screen-rectangle rejection (sg/cull/TriangleClusters.h): after the object test, each drawn geometry
    // not wholly inside the frustum has its triangles, in clusters of screenRectTriangles consecutive ones (index
    // order), left out where the cluster's box lies beyond one side of the viewport; the rest are drawn as index
    // ranges (DrawList::parts). Tested in clip space (x < -w and the like), which for boxes in front of the eye is
    // the paper's "projected rectangle outside the screen" and stays exact for boxes crossing the near plane:
    // conservative in pixels. Not used by CullStrategy::None. Off: items draw whole meshes, as before.
    bool screenRect = false;
    uint32_t screenRectTriangles = 32;  // 1..65536; measured in docs/benchmarks.md (PCVR)

    // Switches that exist to measure the papers' refinements against their absence (sgbench terrain and
    // accuracy): the defaults are what a user wants.
    struct MeasureOnly {
        // A bound whose sphere holds the eye is entered without a test (its children are tested): it is seen,
        // or cut by the near plane. The sphere holds the box, so this also takes every bound whose box holds
        // the eye (the terrain paper's shortcut).
        bool eyeInsideSkip = true;
        // A bound inside a plane frees its subtree of that plane; a bound inside them all, of every test. Off:
        // every bound below is tested against every plane (it costs more and culls the same).
        bool planeMasking = true;
        // The planes tested, one bit each in Camera::eyePlanes() order: left 1, right 2, bottom 4, top 8, near
        // 16, far 32. Leaving planes out (the terrain paper leaves out near, top and bottom: kTerrainPaperPlanes)
        // halves a bound's work and never culls more: it draws a superset, the pixels stay exact.
        uint32_t frustumPlanes = 0x3f;
    };
    MeasureOnly measureOnly;

    // Checks every value, the occlusion and budget parts included: throws SettingError naming `caller` (the
    // entry point, e.g. "CullTraversal::cull()"), the setting, its value and the values allowed. Every entry
    // point that takes CullSettings calls it.
    void validate(const char* caller = "CullSettings::validate()") const;
};

}  // namespace sg
