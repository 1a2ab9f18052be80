// PageRequests: the paged nodes a cull found needed and not loaded, posted from any cull thread and taken by
// the pager on the application thread before the next update, each with how much it is needed.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Node.h"

#include <mutex>
#include <optional>
#include <vector>

namespace sg {

class PageRequests {
public:
    // A node is posted at most once per update (PagedLOD::markNeeded() decides), so the list stays short.
    // `priority`: how much the node's detail is needed, bigger first (CullTraversal::pagedLod() works it out);
    // a node posted again at a later update has its request's priority renewed.
    void post(Node* n) { post(n, 0.0f); }
    // `frame`: the frame the node's detail image is built in (FlatImage::Paged::frame), so that a pager may
    // build it ahead on its loader thread (Scene::buildDetailImage).
    void post(Node* n, float priority, std::optional<dmat4> frame = std::nullopt) {
        std::lock_guard<std::mutex> lock(mutex_);
        posted_.emplace_back(n);
        priorities_.push_back(priority);
        frames_.push_back(frame);
    }
    // Moves the posted nodes into `out` (cleared first), and their priorities into `priorities` (in the same
    // order). The vectors trade storage, so that a steady frame loop allocates nothing.
    void take(std::vector<ref_ptr<Node>>& out) {
        out.clear();
        std::lock_guard<std::mutex> lock(mutex_);
        out.swap(posted_);
        priorities_.clear();
        frames_.clear();
    }
    void take(std::vector<ref_ptr<Node>>& out, std::vector<float>& priorities,
              std::vector<std::optional<dmat4>>& frames) {
        out.clear();
        priorities.clear();
        frames.clear();
        std::lock_guard<std::mutex> lock(mutex_);
        out.swap(posted_);
        priorities.swap(priorities_);
        frames.swap(frames_);
    }
    size_t size() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return posted_.size();
    }

private:
    mutable std::mutex mutex_;
    std::vector<ref_ptr<Node>> posted_;
    std::vector<float> priorities_;  // posted_'s, index for index
    std::vector<std::optional<dmat4>> frames_;
};

}  // namespace sg
