#include "nodes/LOD.h"

#include "nodes/Geometry.h"
#include "sg/NodeVisitor.h"

#include <cmath>
#include <stdexcept>

namespace sg {

void Geometry::accept(NodeVisitor& v) { v.apply(*this); }

void LOD::checkRange(size_t i, float mn, float mx, const char* fn) const {
    auto fail = [&](const std::string& why) {
        throw std::invalid_argument(std::string(fn) + ": " + describe() + " child " + std::to_string(i) + ": range [" +
                                    std::to_string(mn) + ", " + std::to_string(mx) + ") " + why);
    };
    if (std::isnan(mn) || std::isnan(mx)) fail("has a NaN");
    if (mn < 0.0f) fail("starts below 0");
    if (mn > mx) fail("has min > max");
    if (mode_ == Mode::Distance && i > 0 && i - 1 < numChildren() && range(i - 1).min > mn)
        fail("starts before the previous child's range (ranges out of order)");
}

void LOD::addChild(ref_ptr<Node> child, float mn, float mx) {
    checkRange(numChildren(), mn, mx, "LOD::addChild()");
    Group::addChild(std::move(child));
    rangeRef(numChildren() - 1) = Range{mn, mx};
    markDirty(kDirtyBound);
}

void LOD::setRange(size_t i, float mn, float mx) {
    if (i >= numChildren())
        throw std::out_of_range("LOD::setRange(): child " + std::to_string(i) + " of " + describe() + " does not exist");
    checkRange(i, mn, mx, "LOD::setRange()");
    rangeRef(i) = Range{mn, mx};
    markDirty(kDirtyBound);
}

void LOD::setCenter(const dvec3& c) {
    if (!isFinite(c)) throw std::invalid_argument("LOD::setCenter(): " + describe() + ": centre is not finite");
    center_ = c;
    userCenter_ = true;
    markDirty(kDirtyBound);
}

// The children are already inserted or removed when these run: shift the ranges after i.
void LOD::childInserted(size_t i) {
    const size_t n = numChildren();
    if (n > 2) {
        if (!more_) more_ = std::make_unique<std::vector<Range>>();
        more_->emplace_back();
    }
    for (size_t k = n - 1; k > i; --k) rangeRef(k) = rangeRef(k - 1);
    rangeRef(i) = Range{0.0f, 3.4e38f};
}
void LOD::childRemoved(size_t i) {
    const size_t n = numChildren();  // after removal
    for (size_t k = i; k < n; ++k) rangeRef(k) = rangeRef(k + 1);
    if (n >= 2) more_->pop_back();
}
void LOD::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
