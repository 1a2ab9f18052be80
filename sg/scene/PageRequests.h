// PageRequests: the paged nodes a cull found needed and not loaded, posted from any cull thread and taken by
// the pager on the application thread before the next update.
#pragma once
#include "sg/core/Node.h"

#include <mutex>
#include <vector>

namespace sg {

class PageRequests {
public:
    // A node is posted at most once per update (PagedLOD::markNeeded() decides), so the list stays short.
    void post(Node* n) {
        std::lock_guard<std::mutex> lock(mutex_);
        posted_.emplace_back(n);
    }
    // Moves the posted nodes into `out` (cleared first). The two vectors trade storage, so that a steady
    // frame loop allocates nothing.
    void take(std::vector<ref_ptr<Node>>& out) {
        out.clear();
        std::lock_guard<std::mutex> lock(mutex_);
        out.swap(posted_);
    }
    size_t size() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return posted_.size();
    }

private:
    mutable std::mutex mutex_;
    std::vector<ref_ptr<Node>> posted_;
};

}  // namespace sg
