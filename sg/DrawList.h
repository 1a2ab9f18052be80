// DrawList: what the cull selected, in the order the renderer draws it.
#pragma once
#include "sg/Material.h"
#include "sg/Mesh.h"

#include <cstdint>
#include <vector>

namespace sg {

struct DrawItem {
    const Mesh* mesh = nullptr;
    const Material* material = nullptr;
    mat4 model{1.0f};    // local -> eye-relative world (the eye at the origin): float without jitter
    float depth = 0.0f;  // distance of the bound's centre along the view direction
    uint32_t seq = 0;    // emission order: front to back through BspGroups
    uint32_t key = 0;    // state (material, mesh) then depth
};

class DrawList {
public:
    std::vector<DrawItem> items;
    std::vector<uint32_t> order;  // indices into items, sorted by key

    void clear() {
        items.clear();
        order.clear();
        keys_.clear();
    }
    // Appends an item and its sort key (made here, while the item is hot in cache).
    void add(const DrawItem& it) {
        items.push_back(it);
        items.back().key = makeKey(it.mesh, it.material, it.depth);
        keys_.push_back(items.back().key);
    }
    // Sorts `order` by state, then front to back (stable radix sort on the keys made by add()).
    void sort();
    // Order as emitted (no sort).
    void keepEmissionOrder();

    static uint32_t makeKey(const Mesh* mesh, const Material* mat, float depth);

private:
    std::vector<uint32_t> keys_, keysTmp_, work_;
    std::vector<uint32_t> tmp_;
};

}  // namespace sg
