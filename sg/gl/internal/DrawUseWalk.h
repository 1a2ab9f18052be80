// The Geometries below a root as Renderer::DrawUse: each with its mesh and material, whether an LOD above it
// dissolves its children (LOD::transition) and its skin's joints, walked without recursion and able to stop and go
// on later (Renderer::prepare lists a large detail over several frames, within its time budget).
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "sg/gl/Renderer.h"

#include <cstdint>
#include <unordered_set>
#include <utility>
#include <vector>

namespace sg {

class DrawUseWalk {
public:
    explicit DrawUseWalk(const Node& root) : stack_{{&root, false}} {}
    // Calls f(DrawUse) for each Geometry with a mesh, once for each of "below a dissolving LOD" and "not" that
    // some path to it is (shared subgraphs walked once each way); every `every` nodes asks `stop()` and returns
    // false when it says so. Returns true once the walk is done.
    template <class F, class Stop>
    bool run(F&& f, Stop&& stop, size_t every = 256) {
        for (size_t k = 1; !stack_.empty(); ++k) {
            if (k % every == 0 && stop()) return false;
            const auto [n, fades] = stack_.back();
            stack_.pop_back();
            if (!seen_.insert(key(n, fades)).second) continue;
            if (n->kind() == NodeKind::Geometry) {
                const auto& g = static_cast<const Geometry&>(*n);
                if (g.mesh())
                    f(Renderer::DrawUse{g.mesh(), g.material(), fades, g.skin() ? uint32_t(g.skin()->size()) : 0u});
            }
            // The cull gives a fade to what it walks below an LOD's band (CullSettings::lodFade), nested ones too.
            const bool below = fades || (n->kind() == NodeKind::LOD && static_cast<const LOD&>(*n).transition() > 0.0f);
            for (size_t i = 0; i < n->numChildren(); ++i)
                if (const Node* c = n->child(i)) stack_.emplace_back(c, below);
        }
        return true;
    }

private:
    // Nodes are aligned: the low bit of the address is free for the way the node is met.
    static uintptr_t key(const Node* n, bool fades) { return reinterpret_cast<uintptr_t>(n) | (fades ? 1u : 0u); }

    std::vector<std::pair<const Node*, bool>> stack_;
    std::unordered_set<uintptr_t> seen_;
};

}  // namespace sg
