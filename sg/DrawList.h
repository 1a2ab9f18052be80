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
    // Local -> eye-relative world (the eye at the origin): float without jitter. Affine, so its last row
    // (0 0 0 1) is left out: 4 columns of 3, and a whole item fits one 64-byte cache line.
    glm::mat4x3 model;
    mat4 matrix() const { return mat4(model); }
};

class DrawList {
public:
    // Items in emission order (front to back through BspGroups) and, for each, its sort key: state
    // (material, mesh) then the depth of its bound's centre along the view.
    std::vector<DrawItem> items;
    std::vector<uint32_t> order;  // indices into items, sorted by key

    void clear() {
        items.clear();
        order.clear();
        keys_.clear();
    }
    // Appends an item with its depth along the view (its sort key is made here).
    void add(const DrawItem& it, float depth = 0.0f) {
        items.push_back(it);
        keys_.push_back(makeKey(it.mesh, it.material, depth));
    }
    // The cull's way: the key first, then the item filled in place.
    DrawItem& push(uint32_t state, float depth) {
        keys_.push_back(depthKey(state, depth));
        items.emplace_back(Uninitialized{});
        return items.back();
    }
    uint32_t key(size_t i) const { return keys_[i]; }
    // Sorts `order` by state, then front to back (stable radix sort on the keys made by add()/push();
    // items appended to `items` directly sort as depth 0).
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
