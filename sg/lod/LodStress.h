// LodStress: Performer's stress filter. The last frame's load (its time over the budget) moves one LOD
// scale for the whole scene: above `high` the scale grows, below `low` it shrinks back toward 1. Feed it to
// CullSettings::lodScale: coarser levels nearer while the frame is too slow.
#pragma once

namespace sg {

class LodStress {
public:
    struct Params {
        double budgetMs = 33.3;
        double low = 0.8, high = 0.95;  // the load band left alone (fractions of the budget)
        double gain = 1.0;              // scale *= 1 + gain * (load - high), or / (1 + gain * (low - load))
        double maxScale = 16.0;
    };
    // Throws std::invalid_argument naming the parameter: budget not positive, band not 0 < low <= high,
    // gain not positive, maxScale below 1, anything non-finite.
    explicit LodStress(const Params& p);
    LodStress();
    // One frame's measured time; returns the scale for the next frame. Throws std::invalid_argument for a
    // negative or non-finite time.
    double update(double frameMs);
    double scale() const { return scale_; }
    double load() const { return load_; }  // the last frame's time over the budget
    const Params& params() const { return p_; }

private:
    Params p_;
    double scale_ = 1.0;
    double load_ = 0.0;
};

}  // namespace sg
