#include "nodes/PagedLOD.h"

#include "sg/core/NodeVisitor.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace sg {

void PagedLOD::setFile(std::string file, uint32_t part) {
    if (file.empty()) throw std::invalid_argument("PagedLOD::setFile(): " + describe() + ": file name is empty");
    if (state() == State::Requested || state() == State::Loaded)
        throw std::logic_error("PagedLOD::setFile(): " + describe() + ": the detail of '" + file_ +
                               "' is requested or attached; release it first");
    file_ = std::move(file);
    part_ = part;
    failures_ = 0;
    if (state() == State::Failed) setUnloaded();
}

void PagedLOD::setRange(float mn, float mx) {
    if (std::isnan(mn) || std::isnan(mx) || mn < 0.0f || mn > mx)
        throw std::invalid_argument("PagedLOD::setRange(): " + describe() + ": range [" + std::to_string(mn) + ", " +
                                    std::to_string(mx) + ") must have 0 <= min <= max");
    min_ = mn;
    max_ = mx;
    markDirty(kDirtyBound);
}

void PagedLOD::setScreenSpaceError(double geometricError, double maxPixels) {
    if (!(geometricError >= 0.0) || !std::isfinite(geometricError) || !(maxPixels > 0.0) || !std::isfinite(maxPixels))
        throw std::invalid_argument("PagedLOD::setScreenSpaceError(): " + describe() + ": geometric error " +
                                    std::to_string(geometricError) + " and " + std::to_string(maxPixels) +
                                    " pixels must be finite, the error >= 0 and the pixels > 0");
    geometricError_ = geometricError;
    maxPixels_ = maxPixels;
    screenError_ = true;
    markDirty(kDirtyBound);
}

void PagedLOD::setCenter(const dvec3& c) {
    if (!isFinite(c)) throw std::invalid_argument("PagedLOD::setCenter(): " + describe() + ": centre is not finite");
    center_ = c;
    userCenter_ = true;
    markDirty(kDirtyBound);
}

void PagedLOD::setRadius(double r) {
    if (!(r >= 0.0) || !std::isfinite(r))
        throw std::invalid_argument("PagedLOD::setRadius(): " + describe() + ": radius " + std::to_string(r) +
                                    " must be finite and >= 0");
    radius_ = r;
    markDirty(kDirtyBound);
}

void PagedLOD::setRequested() {
    state_.store(State::Requested, std::memory_order_relaxed);
    error_.clear();
}

void PagedLOD::setFailed(std::string error) { setFailed(std::move(error), std::numeric_limits<double>::infinity()); }

void PagedLOD::setFailed(std::string error, double retryTime) {
    state_.store(State::Failed, std::memory_order_relaxed);
    error_ = std::move(error);
    retryTime_.store(retryTime, std::memory_order_relaxed);
    failures_++;
}

void PagedLOD::setUnloaded() {
    state_.store(State::Unloaded, std::memory_order_relaxed);
    error_.clear();
}

void PagedLOD::attachDetail(ref_ptr<Node> detail, size_t bytes) {
    if (!detail) throw std::invalid_argument("PagedLOD::attachDetail(): " + describe() + ": detail is null");
    if (detail_) throw std::logic_error("PagedLOD::attachDetail(): " + describe() + " has a detail attached already");
    detail_ = detail.get();  // first: childChangeMarks() knows it as the detail
    try {
        addChild(std::move(detail));
    } catch (...) {
        detail_ = nullptr;
        throw;
    }
    detailBytes_ = bytes;
    state_.store(State::Loaded, std::memory_order_relaxed);
    error_.clear();
    failures_ = 0;
}

ref_ptr<Node> PagedLOD::detachDetail() {
    ref_ptr<Node> d = detail_;
    if (d) removeChild(d.get());  // childRemoved() forgets it
    setUnloaded();
    return d;
}

void PagedLOD::childRemoved(size_t) {
    // The detail removed by any means (Group::removeChild included) leaves the node Unloaded.
    if (detail_ && indexOf(detail_) == numChildren()) {
        detail_ = nullptr;
        detailBytes_ = 0;
        if (state() == State::Loaded) state_.store(State::Unloaded, std::memory_order_relaxed);
    }
}

void PagedLOD::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
