// DrawList: what the cull selected, in the order the renderer draws it.
#pragma once
#include "sg/Material.h"
#include "sg/Mesh.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace sg {

struct Uninitialized {};

struct DrawItem {
    DrawItem() : model(1.0f) {}
    explicit DrawItem(Uninitialized) {}  // every field is written by the cull right after
    const Mesh* mesh = nullptr;
    const Material* material = nullptr;
    mat4 model;          // local -> eye-relative world (the eye at the origin): float without jitter
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
        keys_.push_back(items.back().key = makeKey(it.mesh, it.material, it.depth));
    }
    // The cull's way: the item is filled in place, then its key is made.
    DrawItem& push() {
        items.emplace_back(Uninitialized{});
        return items.back();
    }
    void pushed(uint32_t state) {
        DrawItem& it = items.back();
        keys_.push_back(it.key = depthKey(state, it.depth));
    }
    // Sorts `order` by state, then front to back (stable radix sort on the keys made by add()).
    void sort();
    // Order as emitted (no sort).
    void keepEmissionOrder();

    // 6 bits of material id and 10 of mesh id, then the top 16 bits of the depth's float bits (monotonic
    // for depth >= 0; about 1/128 relative precision, plenty for front-to-back). Ids that collide only
    // share a sort bucket: the renderer compares pointers before it batches.
    static uint32_t stateKey(const Mesh* mesh, const Material* mat) {
        return ((mat ? mat->id() & 0x3fu : 0u) << 10) | (mesh ? mesh->id() & 0x3ffu : 0u);
    }
    static uint32_t depthKey(uint32_t state, float depth) {
        const float d = depth > 0.0f ? depth : 0.0f;  // NaN fails the test too
        uint32_t bits;
        std::memcpy(&bits, &d, 4);
        return (state << 16) | (bits >> 16);
    }
    static uint32_t makeKey(const Mesh* mesh, const Material* mat, float depth) { return depthKey(stateKey(mesh, mat), depth); }

private:
    std::vector<uint32_t> keys_, keysTmp_, work_, count_;
    std::vector<uint32_t> tmp_;
};

}  // namespace sg
