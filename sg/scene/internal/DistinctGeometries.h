// Each Geometry below a root once, however many paths lead to it (shared subgraphs counted once), walked without
// recursion: what a paged detail holds, to measure (pageBytes), to upload (Renderer::prepare) or to work out ahead.
// Internal header: not installed (an internal/ folder).
#pragma once
#include "nodes/Geometry.h"

#include <unordered_set>
#include <vector>

namespace sg {

// A walk that can stop and go on later: Renderer::prepare lists a large detail's geometries over several frames
// within its time budget, as it uploads them.
class DistinctGeometryWalk {
public:
    explicit DistinctGeometryWalk(const Node& root) : stack_{&root} {}
    // Calls f for each Geometry not met before; every `every` nodes asks `stop()` and returns false when it says
    // so. Returns true once the walk is done.
    template <class F, class Stop>
    bool run(F&& f, Stop&& stop, size_t every = 256) {
        for (size_t k = 1; !stack_.empty(); ++k) {
            if (k % every == 0 && stop()) return false;
            const Node* n = stack_.back();
            stack_.pop_back();
            if (!seen_.insert(n).second) continue;
            if (n->kind() == NodeKind::Geometry) f(*static_cast<const Geometry*>(n));
            for (size_t i = 0; i < n->numChildren(); ++i)
                if (const Node* c = n->child(i)) stack_.push_back(c);
        }
        return true;
    }
    bool done() const { return stack_.empty(); }

private:
    std::vector<const Node*> stack_;
    std::unordered_set<const Node*> seen_;
};

// Each node below a root once (root included), however many paths lead to it.
template <class F>
void forEachDistinctNode(const Node& root, F&& f) {
    std::vector<const Node*> stack{&root};
    std::unordered_set<const Node*> seen;
    while (!stack.empty()) {
        const Node* n = stack.back();
        stack.pop_back();
        if (!seen.insert(n).second) continue;
        f(*n);
        for (size_t i = 0; i < n->numChildren(); ++i)
            if (const Node* c = n->child(i)) stack.push_back(c);
    }
}

template <class F>
void forEachDistinctGeometry(const Node& root, F&& f) {
    DistinctGeometryWalk(root).run(f, [] { return false; });
}

}  // namespace sg
