#include "sg/lod/DrawCostModel.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

namespace {
// Feature scales: a frame draws ~1e5 triangles, ~1e3 items, ~1e6 pixels; scaled to order 1 the fit is
// well conditioned.
constexpr double kTri = 1e-5, kItems = 1e-3, kPixels = 1e-6;
constexpr double kPrior = 100.0;               // initial P = kPrior * I: the prior is weak, data take over at once
constexpr double kMaxTrace = 1e6;              // P grows as 1/lambda^n when frames repeat: bound it
constexpr double kCorrectionFrames = 4.0;      // the correction's time constant, frames
constexpr double kMinCorrection = 1.0 / 16.0;  // a frame can be this much faster or slower than the fit
constexpr double kMaxCorrection = 16.0;
constexpr double kMinTriangleShare = 0.25;    // of the frames' mean time per triangle: a triangle's least price
constexpr double kMeanFrames = 10.0;          // that mean's time constant, frames
constexpr double kMeanMinTriangles = 1000.0;  // frames with fewer triangles tell nothing of them
}  // namespace

DrawCostModel::DrawCostModel(double forgetting) : lambda_(forgetting) {
    if (!(forgetting > 0.0 && forgetting <= 1.0))
        throw std::invalid_argument("DrawCostModel: forgetting " + std::to_string(forgetting) + " is not in (0, 1]");
    w_ = {1.0, 30.0, 0.0, 0.0};
    for (int i = 0; i < kN; ++i)
        for (int j = 0; j < kN; ++j) p_[i][j] = i == j ? kPrior : 0.0;
}

std::array<double, 4> DrawCostModel::features(const Work& w) const {
    return {1.0, w.triangles * kTri, w.items * kItems, w.pixels * kPixels};
}

double DrawCostModel::fit(const Work& w) const {
    const auto x = features(w);
    double y = 0.0;
    for (int i = 0; i < kN; ++i) y += w_[i] * x[i];
    return y;
}

double DrawCostModel::predict(const Work& w) const { return std::max(0.0, correction_ * fit(w)); }

double DrawCostModel::marginal(const Work& w) const {
    const Rates r = rates();
    return r.perTriangle * w.triangles + r.perItem * w.items + r.perPixel * w.pixels;
}

DrawCostModel::Rates DrawCostModel::rates() const {
    const double perTriangle = std::max(w_[1] * kTri, kMinTriangleShare * msPerTriangle_);
    return {correction_ * perTriangle, correction_ * std::max(0.0, w_[2] * kItems),
            correction_ * std::max(0.0, w_[3] * kPixels)};
}

void DrawCostModel::update(const Work& work, double ms) {
    for (double v : {work.triangles, work.items, work.pixels, ms})
        if (!(v >= 0.0 && std::isfinite(v)))
            throw std::invalid_argument("DrawCostModel::update(): " + std::to_string(v) + " is not a count or a time");
    const auto x = features(work);
    // Recursive least squares: gain k = P x / (lambda + x' P x); w += k e; P = (P - k x' P) / lambda.
    std::array<double, kN> px{};
    for (int i = 0; i < kN; ++i)
        for (int j = 0; j < kN; ++j) px[i] += p_[i][j] * x[j];
    double denom = lambda_;
    for (int i = 0; i < kN; ++i) denom += x[i] * px[i];
    double pred = 0.0;
    for (int i = 0; i < kN; ++i) pred += w_[i] * x[i];
    const double e = ms - pred;
    lastError_ = ms - correction_ * pred;
    for (int i = 0; i < kN; ++i) w_[i] += px[i] / denom * e;
    double trace = 0.0;
    for (int i = 0; i < kN; ++i)
        for (int j = 0; j < kN; ++j) {
            p_[i][j] = (p_[i][j] - px[i] * px[j] / denom) / lambda_;
            if (i == j) trace += p_[i][j];
        }
    for (int i = 0; i < kN; ++i)  // symmetric by construction; rounding drifts it apart: average
        for (int j = i + 1; j < kN; ++j) p_[i][j] = p_[j][i] = 0.5 * (p_[i][j] + p_[j][i]);
    if (trace > kMaxTrace)
        for (auto& row : p_)
            for (double& v : row) v *= kMaxTrace / trace;
    if (work.triangles >= kMeanMinTriangles) {
        const double perTriangle = ms / work.triangles;
        msPerTriangle_ =
            msPerTriangle_ > 0.0 ? msPerTriangle_ + (perTriangle - msPerTriangle_) / kMeanFrames : perTriangle;
    }
    samples_++;
}

void DrawCostModel::correct(double plannedMs, double measuredMs) {
    for (double v : {plannedMs, measuredMs})
        if (!(v >= 0.0 && std::isfinite(v)))
            throw std::invalid_argument("DrawCostModel::correct(): " + std::to_string(v) + " is not a time");
    // In ratios, smoothed: one slow frame moves the prices by a quarter of its excess at most (in logs), a
    // load that doubles every frame's time doubles them within a few frames.
    const double ratio = std::clamp(measuredMs / std::max(plannedMs, 1e-3), 0.25, 4.0);
    correction_ = std::clamp(correction_ * std::pow(ratio, 1.0 / kCorrectionFrames), kMinCorrection, kMaxCorrection);
}

}  // namespace sg
