// Accuracy harness: renders each view with culling off (the reference) and with a cull setting, headless,
// and counts the pixels that differ. A conservative strategy must give 0 on every view.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"

#include <memory>
#include <string>
#include <vector>

namespace accuracy {

struct Result {
    std::string name;  // settingName() of the setting
    int views = 0;
    uint64_t differingTotal = 0;
    uint64_t differingMax = 0;
    int viewsWithError = 0;
    int worstView = -1;
    double framePixels = 0;  // pixels in one view
    std::vector<uint64_t> perView;
    // What the cull did, summed over the views: shows that a setting was not vacuous (an occlusion pass
    // that culls nothing is trivially exact).
    uint64_t culledOcclusionTotal = 0;     // CullStats::culledOcclusion
    uint64_t occludersUsedTotal = 0;       // CullStats::occludersUsed
    int viewsOcclusionRan = 0;             // views where the occlusion tree was built
    int viewsWithOcclusionCulls = 0;       // views where it culled at least one bound
    uint64_t trianglesTotal = 0;           // CullStats::triangles: triangles drawn
    uint64_t referenceTrianglesTotal = 0;  // triangles drawn by the reference (no culling)
    std::vector<uint64_t> perViewCulledOcclusion;
    double percentOfFrames() const { return views ? 100.0 * double(differingTotal) / (framePixels * views) : 0.0; }
};

// "aabb", "center-box+small-feature", "aabb+screen-rect", "aabb+occlusion" (mode EveryFrame),
// "aabb+occlusion-adaptive", and
// "-centre" appended for the centre-plane cap, e.g. "aabb+occlusion-centre", "-hom" or "-hom-approx" for the occlusion
// map. The occlusion part is left out when the mode is Off or the strategy is None (which disables occlusion).
std::string settingName(const sg::CullSettings& s);

// Every conservative method: the three frustum strategies alone (sphere, aabb, sphere-sphere), then boxes
// with the occlusion tree and with the occlusion map, both every frame (mode EveryFrame: Adaptive could skip frames).
std::vector<sg::CullSettings> conservativeSettings();

// The camera in one line: eye, target (eye + view direction), up, vertical fov, near and far (perspective).
std::string describeCamera(const sg::Camera& c);

class Harness {
public:
    // Throws std::runtime_error when no OSMesa context can be made.
    Harness(int width, int height);
    // Every setting against the same reference render of each view. Each setting has its own traversal,
    // so the occlusion pass's Adaptive state follows the views in order, as it would follow frames.
    std::vector<Result> run(const sg::Scene& scene, const std::vector<sg::Camera>& views,
                            const std::vector<sg::CullSettings>& settings);
    // One view: the reference and the culled image (for a test's failure message or a PNG), and the
    // culled render's stats.
    uint64_t compare(const sg::Scene& scene, const sg::Camera& view, const sg::CullSettings& s,
                     sg::Image* ref = nullptr, sg::Image* got = nullptr, sg::CullStats* stats = nullptr);

private:
    sg::Image render(sg::CullTraversal& cull, const sg::Scene& scene, const sg::Camera& view, const sg::CullSettings& s,
                     sg::CullStats& st);
    int w_, h_;
    sg::OsmesaContext ctx_;
    std::unique_ptr<sg::Renderer> renderer_;
    sg::CullTraversal refCull_;
    std::vector<std::unique_ptr<sg::CullTraversal>> culls_;  // one per setting of run()
    sg::CullTraversal compareCull_;
    sg::DrawList list_;
};

// View sets: cameras of every awkward kind (inside objects, straight down, near plane cutting objects,
// very wide and very narrow fields of view), at the harness's viewport size.
std::vector<sg::Camera> cityViews(int n, int count, uint64_t seed, int width, int height);
std::vector<sg::Camera> boxViews(const sg::Box& bounds, int count, uint64_t seed, int width, int height);

// Occlusion views of `city` (built with occluders): half at street level (eye 1.5-2 m high in the streets,
// random yaw, small pitch), half aerial (30-800 m above, looking down obliquely or steeply), with awkward
// ones among them: the eye exactly in a building face's plane or on a face, very close to a building,
// looking exactly along a street, level with a roof, straight down.
std::vector<sg::Camera> cityOcclusionViews(int n, int count, uint64_t seed, int width, int height);
// Views of `office` (R x R rooms): mostly inside (eye 1.2-1.8 m in random rooms, random yaw, small pitch;
// standing in door openings, looking through doors, the eye in a wall's face plane or very close to a
// wall), and some from above (there is no ceiling), a few level with the walls' tops.
std::vector<sg::Camera> officeViews(int r, int count, uint64_t seed, int width, int height);

}  // namespace accuracy
