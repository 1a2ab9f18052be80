#include "sg/core/Ref.h"

namespace sg {

thread_local DeferredRelease* DeferredRelease::current_ = nullptr;

DeferredRelease::DeferredRelease() noexcept : outer_(current_) { current_ = this; }

DeferredRelease::~DeferredRelease() {
    current_ = outer_;
    if (queue_.empty()) return;
    if (outer_) {
        outer_->queue_.insert(outer_->queue_.end(), queue_.begin(), queue_.end());
        return;
    }
    releaseNow(queue_);
}

void Referenced::release() const {
    // Out of line, so that the thread-local lookup costs nothing on the unrefs that leave a count above 0.
    if (DeferredRelease* d = DeferredRelease::current_)
        d->queue_.push_back(this);
    else
        delete this;
}

void releaseNow(std::vector<const Referenced*>& objects) {
    // Taken first: deleting one may queue more into a scope on this thread, never into this vector.
    std::vector<const Referenced*> v = std::exchange(objects, {});
    for (const Referenced* o : v) delete o;
}

}  // namespace sg
