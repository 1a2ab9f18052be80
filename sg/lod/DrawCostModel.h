// DrawCostModel: predicts the draw time of what a frame draws (triangles, draw items, covered pixels) with
// a linear model fitted online to measured times, so that a time budget can be planned before drawing.
// Recursive least squares with a forgetting factor: this machine's speed drifts by tens of percent over
// seconds, so old frames count less than recent ones. On top of the fit, a correction factor closes the
// loop on what a plan predicted: the budget plans with the fit's prices, the frame takes what it takes,
// and their ratio, smoothed over a few frames, scales every price. The fit follows the machine over
// ~1 / (1 - forgetting) frames and mixes its parts up when frames repeat (the fixed part and the rates are
// then told apart by noise); the correction follows a background load within a few frames both ways.
#pragma once
#include "sg/core/Mesh.h"

#include <array>
#include <cstdint>

namespace sg {

// What the model counts as triangles: a point or a line segment is drawn as a quad of two triangles (Mesa's draw
// module widens each into one; what that costs against triangles is measured in docs/benchmarks.md "Points and
// lines"), so the budget prices scans and edges with the rate it learns from triangles.
constexpr double kQuadTriangles = 2.0;
inline double triangleWork(double triangles, double points, double lines) {
    return triangles + kQuadTriangles * (points + lines);
}
inline double triangleWork(const Mesh& m) { return triangleWork(m.triangleCount(), m.pointCount(), m.lineCount()); }

class DrawCostModel {
public:
    struct Work {
        double triangles = 0.0;  // with points and line segments as triangleWork() counts them
        double items = 0.0;      // draw items (instances)
        double pixels = 0.0;     // covered pixels, estimated (projected bound areas)
    };
    // forgetting in (0, 1]: each frame, older frames' weight is multiplied by it (1: remember all).
    // Throws std::invalid_argument naming the value otherwise.
    explicit DrawCostModel(double forgetting = 0.98);

    // Predicted milliseconds for this much work (never negative). Before any measurement: a prior of
    // 1 ms per frame plus 30 ms per 100,000 triangles (llvmpipe at 1280x720 on this kind of machine).
    double predict(const Work& w) const;
    // The cost of adding this work to a frame (the fixed per-frame part left out): what one object costs.
    double marginal(const Work& w) const;
    // marginal() as milliseconds per unit of each kind of work, to price many objects in a loop: the cost
    // of w is perTriangle * w.triangles + perItem * w.items + perPixel * w.pixels. No rate is negative, and a
    // triangle costs at least a quarter of what recent frames took per triangle drawn (all their time over
    // all their triangles): on a path the fit's parts move together and its own triangle rate can come out
    // at zero or below, and a budget that prices triangles at nothing buys the finest level of everything.
    struct Rates {
        double perTriangle, perItem, perPixel;
    };
    Rates rates() const;
    // One frame: the work it drew and its measured draw time. Throws std::invalid_argument for a negative
    // or non-finite value.
    void update(const Work& w, double measuredMs);
    // One planned frame: it was to take plannedMs by this model's prices (predict() of what it drew) and
    // took measuredMs. Every price is multiplied by the correction, which moves by their ratio: a quarter
    // of it per frame in logs (a time constant of 4 frames), ratios beyond 4x counted as 4x, the
    // correction within 1/16..16. Throws std::invalid_argument for a negative or non-finite time.
    void correct(double plannedMs, double measuredMs);
    uint64_t samples() const { return samples_; }
    double correction() const { return correction_; }  // 1 until correct() is called
    double lastError() const { return lastError_; }    // measured minus predicted (before it), ms, of the last update

private:
    static constexpr int kN = 4;  // 1, triangles, items, pixels (each scaled to order 1)
    std::array<double, kN> features(const Work& w) const;
    double fit(const Work& w) const;  // the fit alone, without the correction
    double lambda_;
    std::array<double, kN> w_;
    std::array<std::array<double, kN>, kN> p_;  // inverse correlation, kept symmetric and bounded
    uint64_t samples_ = 0;
    double lastError_ = 0.0;
    double correction_ = 1.0;
    double msPerTriangle_ = 0.0;  // recent frames' time over their triangles, smoothed (0: none yet)
};

}  // namespace sg
