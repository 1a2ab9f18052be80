#include "nodes/LOD.h"

#include "sg/core/NodeVisitor.h"

#include <cmath>
#include <stdexcept>

namespace sg {

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
        throw std::out_of_range("LOD::setRange(): child " + std::to_string(i) + " of " + describe() +
                                " does not exist");
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

void LOD::setTransition(float width) {
    if (!(width >= 0.0f && std::isfinite(width)))
        throw std::invalid_argument("LOD::setTransition(): " + describe() + ": width " + std::to_string(width) +
                                    " is not finite and non-negative");
    transition_ = width;
    markDirty(kDirtyBound);  // the image keeps a copy
}

void LOD::setError(size_t i, float e) {
    if (i >= numChildren())
        throw std::out_of_range("LOD::setError(): child " + std::to_string(i) + " of " + describe() +
                                " does not exist");
    if (!(e >= 0.0f && std::isfinite(e)))
        throw std::invalid_argument("LOD::setError(): " + describe() + " child " + std::to_string(i) + ": error " +
                                    std::to_string(e) + " is not finite and non-negative");
    if (!more_ || more_->errors.empty()) {
        if (!more_) more_ = std::make_unique<More>();
        more_->errors.assign(numChildren(), 0.0f);
    }
    more_->errors[i] = e;
    markDirty(kDirtyBound);  // the image keeps a copy (the LOD budget values levels by it)
}

float LOD::error(size_t i) const {
    if (i >= numChildren())
        throw std::out_of_range("LOD::error(): child " + std::to_string(i) + " of " + describe() + " does not exist");
    return more_ && !more_->errors.empty() ? more_->errors[i] : 0.0f;
}

// The children are already inserted or removed when these run: shift the ranges (and errors) after i.
void LOD::childInserted(size_t i) {
    const size_t n = numChildren();
    if (n > 2) {
        if (!more_) more_ = std::make_unique<More>();
        more_->ranges.emplace_back();
    }
    for (size_t k = n - 1; k > i; --k) rangeRef(k) = rangeRef(k - 1);
    rangeRef(i) = Range{0.0f, 3.4e38f};
    if (more_ && !more_->errors.empty()) more_->errors.insert(more_->errors.begin() + std::ptrdiff_t(i), 0.0f);
    SG_ASSERT(n <= 2 || more_->ranges.size() == n - 2, "LOD::childInserted(): ranges out of step with the children");
}
void LOD::childRemoved(size_t i) {
    const size_t n = numChildren();  // after removal
    for (size_t k = i; k < n; ++k) rangeRef(k) = rangeRef(k + 1);
    if (n >= 2) more_->ranges.pop_back();
    if (more_ && !more_->errors.empty()) more_->errors.erase(more_->errors.begin() + std::ptrdiff_t(i));
    SG_ASSERT(!more_ || more_->ranges.size() == (n > 2 ? n - 2 : 0),
              "LOD::childRemoved(): ranges out of step with the children");
}
void LOD::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
