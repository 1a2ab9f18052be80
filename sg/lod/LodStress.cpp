#include "sg/lod/LodStress.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

namespace {
void check(bool ok, const char* what, double v) {
    if (!ok)
        throw std::invalid_argument(std::string("LodStress: ") + what + " " + std::to_string(v) + " is out of range");
}
}  // namespace

LodStress::LodStress() : LodStress(Params{}) {}

LodStress::LodStress(const Params& p) : p_(p) {
    check(p.budgetMs > 0 && std::isfinite(p.budgetMs), "budgetMs", p.budgetMs);
    check(p.low > 0 && std::isfinite(p.low), "low", p.low);
    check(p.high >= p.low && std::isfinite(p.high), "high", p.high);
    check(p.gain > 0 && std::isfinite(p.gain), "gain", p.gain);
    check(p.maxScale >= 1 && std::isfinite(p.maxScale), "maxScale", p.maxScale);
}

double LodStress::update(double frameMs) {
    if (!(frameMs >= 0 && std::isfinite(frameMs)))
        throw std::invalid_argument("LodStress::update(): frame time " + std::to_string(frameMs) + " ms is not a time");
    load_ = frameMs / p_.budgetMs;
    // Multiplicative steps: the same relative correction whatever the scale already is. The step is
    // proportional to how far the load is out of the band, so it settles instead of swinging.
    if (load_ > p_.high)
        scale_ *= 1.0 + p_.gain * (load_ - p_.high);
    else if (load_ < p_.low)
        scale_ /= 1.0 + p_.gain * (p_.low - load_);
    scale_ = std::clamp(scale_, 1.0, p_.maxScale);
    return scale_;
}

}  // namespace sg
