// Each Geometry below a root once, however many paths lead to it (shared subgraphs counted once), walked without
// recursion: what a paged detail holds, to measure (pageBytes), to upload (Renderer::prepare) or to work out ahead.
// Internal header: not installed (SGKIT_INTERNAL_HEADERS in cmake/LayerCheck.cmake).
#pragma once
#include "nodes/Geometry.h"

#include <unordered_set>
#include <vector>

namespace sg {

template <class F>
void forEachDistinctGeometry(const Node& root, F&& f) {
    std::vector<const Node*> stack{&root};
    std::unordered_set<const Node*> seen;
    while (!stack.empty()) {
        const Node* n = stack.back();
        stack.pop_back();
        if (!seen.insert(n).second) continue;
        if (n->kind() == NodeKind::Geometry) f(*static_cast<const Geometry*>(n));
        for (size_t i = 0; i < n->numChildren(); ++i)
            if (const Node* c = n->child(i)) stack.push_back(c);
    }
}

}  // namespace sg
