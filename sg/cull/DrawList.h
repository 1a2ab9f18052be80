// DrawList: what the cull selected, in the order the renderer draws it.
#pragma once
#include "sg/core/Assert.h"
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"
#include "sg/core/Pose.h"

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

// Indices [first, first + count) of an item's mesh (CullSettings::screenRect draws items in part).
struct IndexRange {
    uint32_t first, count;
};

class DrawList {
public:
    // Items in emission order (front to back through BspGroups) and, for each, its sort key: state
    // (material, mesh) then the depth of its geometry's origin (its matrix's translation) along the view.
    std::vector<DrawItem> items;
    std::vector<uint32_t> order;  // indices into items, sorted by key
    // Items drawn dissolved (LOD fade), by item index, in emission order: f in (0, 1) keeps the pixels whose
    // screen-door pattern value is below f, f in (-1, 0) those at or above 1 + f. Items not listed: opaque.
    std::vector<std::pair<uint32_t, float>> fades;
    // Items drawn in part (CullSettings::screenRect), by item index: the item draws only the index ranges
    // ranges[first, first + count), ascending and disjoint. Items not listed: their whole mesh.
    struct Part {
        uint32_t item, first, count;
        // The ranges hold every triangle of the item that reaches the screen (the cull's screen-rect parts): the
        // front faces in front of its back faces are drawn, so the renderer may skip the back faces of a closed mesh
        // (Renderer::setBackFaceCulling). Parts of other making draw exactly their triangles, back faces too.
        bool coversScreen = false;
    };
    std::vector<Part> parts;
    std::vector<IndexRange> ranges;
    // Items below a node that is a feature (Node::setFeatures): items [first, end) in emission order were emitted
    // below a node whose sets and index these are (a style colours or hides the items by them). A range is added
    // once the walk leaves the node's subtree, so an inner node's comes before the outer one's that holds it: an
    // item's feature is that of the first range holding it. Items in no range: no such node.
    struct Feature {
        uint32_t first, end;
        const MeshFeatures* features;
        uint32_t index;
    };
    std::vector<Feature> features;
    // Items of posed Geometries (skinned or morphed: sg/core/Pose.h), by item index, in emission order. The renderer
    // draws the pose's mesh (Pose::drawn) and, for a skinned pose, skins it with the pose's joint matrices, the item's
    // matrix then the translation from the eye to Pose::anchor. The pose stays alive while the list is drawn (the
    // viewer's packet holds it).
    std::vector<std::pair<uint32_t, const Pose*>> poses;

    void clear() {
        items.clear();
        order.clear();
        fades.clear();
        parts.clear();
        features.clear();
        poses.clear();
        ranges.clear();
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
    uint32_t key(size_t i) const {
        SG_ASSERT(i < keys_.size(), "DrawList::key(): item past the keys");
        return keys_[i];
    }
    // Sorts `order` by state, then front to back (stable radix sort on the keys made by add()/push();
    // items appended to `items` directly sort as depth 0).
    void sort();
    // Order as emitted (no sort).
    void keepEmissionOrder();

    // A 22-bit key, sorted in two 11-bit passes: 10 bits of state, then the depth's exponent and top
    // 3 mantissa bits (monotonic for depth >= 0; buckets 12% apart, plenty for front to back). The cull
    // passes a dense state index per mesh/material pair; states that share 10 bits only share a sort
    // bucket: the renderer compares pointers before it batches.
    static uint32_t stateKey(const Mesh* mesh, const Material* mat) {
        return ((mat ? mat->id() * 37u : 0u) + (mesh ? mesh->id() : 0u)) & 0x3ffu;
    }
    static uint32_t depthKey(uint32_t state, float depth) {
        const float d = depth > 0.0f ? depth : 0.0f;  // NaN fails the test too
        uint32_t bits;
        std::memcpy(&bits, &d, 4);
        return ((state & 0x3ffu) << 12) | (bits >> 19);
    }
    static uint32_t makeKey(const Mesh* mesh, const Material* mat, float depth) {
        return depthKey(stateKey(mesh, mat), depth);
    }

private:
    std::vector<uint32_t> keys_, keysTmp_, work_, count_;
    std::vector<uint32_t> tmp_;
};

}  // namespace sg
