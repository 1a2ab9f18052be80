// LOD: shows the children whose range holds the eye's distance to a centre, or the projected pixel size.
#pragma once
#include "nodes/Group.h"
#include "sg/Math.h"

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
    const Range& range(size_t i) const { return i < 2 ? inline_[i] : (*more_)[i - 2]; }

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
    Range& rangeRef(size_t i) { return i < 2 ? inline_[i] : (*more_)[i - 2]; }
    dvec3 center_{0.0};
    Range inline_[2];                              // most LODs have two levels: no allocation for them
    std::unique_ptr<std::vector<Range>> more_;     // ranges of children 2 and up
    Mode mode_ = Mode::Distance;
    bool userCenter_ = false;
};

}  // namespace sg
