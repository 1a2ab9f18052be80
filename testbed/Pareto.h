// Run time against error for every cull and LOD method on a scene (sgbench pareto): each method's frames timed
// beside the others', its pictures compared with the unculled full-detail render, the Pareto front marked.
#pragma once
#include "sg/cull/CullSettings.h"
#include "sg/gl/Renderer.h"
#include "sg/scene/Scene.h"
#include "testbed/LodRun.h"

#include <functional>
#include <string>
#include <vector>

namespace pareto {

// One way to cull and choose levels: the settings every frame starts from and the LOD method driving them.
struct Method {
    std::string name;
    sg::CullSettings cull;
    sg::LodPolicy lod = sg::LodPolicy::Static;
    bool conservative = false;  // culls only what cannot be seen: 0 differing pixels where LODs do not differ
    bool isDefault = false;     // CullSettings{} with the scene's static LOD ranges
    bool needsLods = false;     // only on scenes with LODs (the stress and budget methods)
    // Drawn through sg::OcclusionQueries (its own, following the views as frames): the items whose bounding box
    // showed no sample in the method's previous frame are left out.
    bool gpuQueries = false;
};

// The table every scene runs, in this order: none, center-box, sphere, sphere-sphere, aabb, aabb with
// small-feature 1, 2, 4 px, the occlusion tree, hom, hom-approx (each every frame), gpu-query (aabb, then hardware
// occlusion queries on the items' boxes, a frame late), the default, LOD stress, LOD budget.
std::vector<Method> methods();
// The methods whose names are in the comma-separated `names` (all when empty), in the table's order. Throws
// std::invalid_argument naming an unknown method and listing the valid ones.
std::vector<Method> selectMethods(const std::vector<Method>& all, const std::string& names);

// A scene as pareto measures it: its views, in path order, at the viewport they are drawn at.
struct SceneViews {
    std::string name;
    sg::Scene* scene = nullptr;
    std::vector<sg::Camera> views;
    std::function<void(size_t)> prepare;  // the scene's state for view i (the factory's switches); may be empty
    bool hasLods = false;
};

struct Options {
    int rounds = 1;                // timed passes over the views (the first also counts the errors)
    double budgetMs = 33.0;        // what the LOD stress and budget methods aim at (Method::lod)
    bool strictReference = false;  // reference drawn with CullStrategy::None (else Aabb: the same pixels, cheaper)
};

// One (scene, method): medians over every timed frame, means over the views.
struct Row {
    std::string scene, method;
    bool conservative = false, isDefault = false, onFront = false;
    int views = 0, rounds = 0, width = 0, height = 0;
    double cullMs = 0.0, frameMs = 0.0;        // median per frame; frame: cull + draw + glFinish
    double cullRatio = 0.0, frameRatio = 0.0;  // to `none`'s medians on the same scene (0 without a `none` row)
    double objects = 0.0, triangles = 0.0;     // drawn, mean per view
    double errorPixels = 0.0;                  // differing from the reference, mean per view
    double errorPercent = 0.0;                 // of the view's pixels
    int viewsWithError = 0;
    double wronglyCulled = 0.0;  // reference-visible geometries the method did not draw, mean per view
    uint64_t wronglyCulledTotal = 0;
    double queries = 0.0;  // occlusion queries issued per frame, mean per view (Method::gpuQueries; else 0)
    // Every timed frame's ms, round by round, view by view: the same order for every method of a scene, so that
    // two methods compare frame by frame (the view's own cost cancels).
    std::vector<double> frames = {};
};

// Every method on every view, methods interleaved per view (each view starts one further along the table, so
// that drift and cache warmth hit all alike), with `renderer`'s context current at the views' viewport. Errors
// come from the first round: per view, the reference is `scene` drawn unculled with every LOD at its finest
// level; pixels differing from it are counted, and geometries whose id shows in an id render of the reference
// (each geometry unlit in a colour of its own) but that the method's draw list misses are wrongly culled; a
// geometry drawn at another level (another mesh at the same place, not in the reference there) counts as drawn.
// Throws std::invalid_argument for no views or methods, or rounds below 1.
std::vector<Row> measure(sg::Renderer& renderer, const SceneViews& scene, const std::vector<Method>& methods,
                         const Options& options);

// onFront[i]: no point is both faster (time below) and at most as wrong (error at most). Throws
// std::invalid_argument when the sizes differ.
std::vector<bool> paretoFront(const std::vector<double>& time, const std::vector<double>& error);
// Row::onFront by frame ms and error pixels, per scene.
void markFront(std::vector<Row>& rows);

// The CSV header line (no newline) and the table: one row per scene and method.
std::string csvHeader();
std::string csv(const std::vector<Row>& rows);
// A markdown table per scene, front members in bold, the default marked.
std::string markdown(const std::vector<Row>& rows);
// A scene whose default row is not on its front, and the methods that beat it (faster, at most as wrong).
struct OffFront {
    std::string scene;
    bool beyondNoise = false;  // some method is faster by more than the tolerance, frame by frame
    std::string text;  // "scene: the default (... ms, error ...) is beaten by method (ms, error, frame by frame ...)"
};
// `tolerance`: the share of the default's frame time a method must save to be beyond noise (e.g. 0.05), judged on
// the median over frames of the method's time over the default's in the same frame (Row::frames; the ratio of
// the medians when the rows have no frames).
std::vector<OffFront> defaultOffFront(const std::vector<Row>& rows, double tolerance);
// A gnuplot script (data inline) drawing `png`: x error pixels + 1 (log), y frame ms as a ratio to none (log),
// one colour per scene, each front joined by a line.
std::string gnuplotScript(const std::vector<Row>& rows, const std::string& png);

}  // namespace pareto
