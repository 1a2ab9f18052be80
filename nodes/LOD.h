// LOD: shows the children whose range holds the eye's distance to a centre, or the projected pixel size.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Assert.h"
#include "sg/core/Math.h"

#include <memory>
#include <vector>

namespace sg {

class LOD : public Group {
public:
    enum class Mode : uint8_t { Distance, PixelSize };
    struct Range {
        float min = 0.0f, max = 0.0f;  // child shown when min <= value < max
    };

    LOD() : Group(NodeKind::LOD) {}

    // Adds a child with its range. Throws std::invalid_argument when min > max, either is NaN or negative,
    // or (Distance mode) the range starts before the previous child's range starts (out of order).
    void addChild(ref_ptr<Node> child, float min, float max);
    void setRange(size_t i, float min, float max);
    // The range of child i; i < numChildren().
    const Range& range(size_t i) const {
        SG_ASSERT(i < numChildren(), "LOD::range(): child index past the children");
        return i < 2 ? inline_[i] : more_->ranges[i - 2];
    }
    // Geometric error of child i in the LOD's units (the deviation of that level from the full detail one),
    // 0 unless set; it follows its child when children are inserted or removed, as the range does. sg::makeLod
    // stores them; the LOD budget (CullSettings::lodBudget) values levels by them once any is set, even to 0
    // (a coarse level of the same shape is as good as the fine one), and guesses from triangle counts
    // otherwise. setError throws std::invalid_argument for a negative or non-finite error, both throw
    // std::out_of_range for a bad index.
    void setError(size_t i, float error);
    float error(size_t i) const;
    bool hasErrors() const { return more_ && !more_->errors.empty(); }

    // Performer's LOD fade: over a band `width` wide (in the LOD's units: distance, or pixels) centred on each
    // end of a child's range, the child dissolves in or out with a screen-door pattern instead of popping; two
    // children that meet at a boundary get complementary patterns there, so each pixel shows exactly one of
    // them. 0 (the default): no band, the child pops. Throws std::invalid_argument for a negative or
    // non-finite width. CullSettings::lodFade turns every band off at once.
    void setTransition(float width);
    float transition() const { return transition_; }

    void setMode(Mode m) {
        mode_ = m;
        markDirty(kDirtyBound);  // the image keeps a copy of the mode and ranges
    }
    Mode mode() const { return mode_; }
    // Centre in the LOD's frame. By default the centre of the LOD's bound (computed by the update pass).
    void setCenter(const dvec3& c);
    const dvec3& center() const { return center_; }
    bool userCenter() const { return userCenter_; }

    void accept(NodeVisitor& v) override;

protected:
    void childInserted(size_t i) override;
    void childRemoved(size_t i) override;

private:
    void checkRange(size_t i, float min, float max, const char* fn) const;
    // While children are inserted or removed the ranges lag the children by one: checked against the storage.
    Range& rangeRef(size_t i) {
        SG_ASSERT(i < 2 || (more_ && i - 2 < more_->ranges.size()), "LOD::rangeRef(): index past the stored ranges");
        return i < 2 ? inline_[i] : more_->ranges[i - 2];
    }
    // What does not fit inline shares one allocation, so that a plain two-level LOD stays as small as it was.
    struct More {
        std::vector<Range> ranges;  // ranges of children 2 and up
        std::vector<float> errors;  // one per child once any error is set, empty before
    };
    dvec3 center_{0.0};
    Range inline_[2];             // most LODs have two levels: no allocation for them
    std::unique_ptr<More> more_;  // null while there are at most two children and no errors
    Mode mode_ = Mode::Distance;
    bool userCenter_ = false;
    float transition_ = 0.0f;
};

}  // namespace sg
