// Accuracy harness: renders each view with culling off (the reference) and with a cull setting, headless,
// and counts the pixels that differ. A conservative strategy must give 0 on every view.
#pragma once
#include "sg/CullTraversal.h"
#include "sg/ImageIO.h"
#include "sg/OsmesaContext.h"
#include "sg/Renderer.h"

#include <memory>
#include <vector>

namespace accuracy {

struct Result {
    std::string name;
    int views = 0;
    uint64_t differingTotal = 0;
    uint64_t differingMax = 0;
    int viewsWithError = 0;
    int worstView = -1;
    double framePixels = 0;  // pixels in one view
    std::vector<uint64_t> perView;
    double percentOfFrames() const { return views ? 100.0 * double(differingTotal) / (framePixels * views) : 0.0; }
};

class Harness {
public:
    // Throws std::runtime_error when no OSMesa context can be made.
    Harness(int width, int height);
    // Every setting against the same reference render of each view.
    std::vector<Result> run(const sg::Scene& scene, const std::vector<sg::Camera>& views,
                            const std::vector<sg::CullSettings>& settings);
    // One view: the reference and the culled image (for a test's failure message or a PNG).
    uint64_t compare(const sg::Scene& scene, const sg::Camera& view, const sg::CullSettings& s, sg::Image* ref = nullptr,
                     sg::Image* got = nullptr);

private:
    sg::Image render(const sg::Scene& scene, const sg::Camera& view, const sg::CullSettings& s);
    int w_, h_;
    sg::OsmesaContext ctx_;
    std::unique_ptr<sg::Renderer> renderer_;
    sg::CullTraversal cull_;
    sg::DrawList list_;
};

// View sets: cameras of every awkward kind (inside objects, straight down, near plane cutting objects,
// very wide and very narrow fields of view), at the harness's viewport size.
std::vector<sg::Camera> cityViews(int n, int count, uint64_t seed, int width, int height);
std::vector<sg::Camera> boxViews(const sg::Box& bounds, int count, uint64_t seed, int width, int height);

}  // namespace accuracy
