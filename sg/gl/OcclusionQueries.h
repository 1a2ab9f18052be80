// OcclusionQueries: hardware occlusion queries on the items' bounding boxes, as OpenSceneGraph's OcclusionQueryNode
// does them: every frame each item's world box is drawn, invisibly, under a query after the frame's items, and an
// item whose box showed no sample is left out of the next frame (one frame of latency: not conservative).
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/DrawList.h"
#include "sg/gl/Renderer.h"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace sg {

class OcclusionQueries {
public:
    // What the last frame did.
    struct Stats {
        uint32_t queries = 0;          // boxes queried (every item of the list but those near the eye and posed ones)
        uint32_t hidden = 0;           // items left out: their box showed no sample in the frame before
        uint64_t hiddenTriangles = 0;  // their triangles (the parts' for items drawn in part)
        uint32_t nearEye = 0;  // items drawn unqueried: their box reaches the near plane, which could clip it away
    };

    // Needs a current OpenGL 3.3 core context (the renderer's), which must stay alive and be current whenever this
    // is used or destroyed. Throws std::runtime_error when its program does not build.
    OcclusionQueries();
    ~OcclusionQueries();
    OcclusionQueries(const OcclusionQueries&) = delete;
    OcclusionQueries& operator=(const OcclusionQueries&) = delete;

    // One frame: the results of the frame before are read; `renderer` draws the items of `list` whose box was seen
    // then, or that had no query (new in view, or near the eye), and queries the box of every item of `list` (those
    // just left out too, so that they come back) after its items, against the frame's depth.
    void draw(Renderer& renderer, const DrawList& list, const Camera& camera,
              const vec4& clearColor = Renderer::kClearColor);
    // The items the last draw() drew (list's items, order, fades, parts and poses, less the hidden ones). Posed items
    // (DrawList::poses) are always drawn and never queried.
    const DrawList& drawn() const { return drawn_; }
    const Stats& lastStats() const { return stats_; }
    // Forgets every result: the next frame draws all its items.
    void reset();

    // draw()'s two halves, for a frame loop of its own: select() reads the last results and fills `drawn`; issue()
    // is the renderer's AfterItems pass (Renderer::setAfterItems) for the draw of `drawn`.
    void select(const DrawList& list, const Camera& camera, DrawList& drawn);
    void issue(const mat4& viewProj, bool reverseDepth);

    // Where an item stands, the same from frame to frame whatever the eye: its mesh and material, its world position
    // to the millimetre (the matrix's translation plus the eye) and its rotation and scale to 1e-5.
    struct Key {
        const Mesh* mesh;
        const Material* material;
        int64_t x, y, z;
        uint64_t basis;  // a hash of the rounded 3x3 part
        bool operator==(const Key& o) const {
            return mesh == o.mesh && material == o.material && x == o.x && y == o.y && z == o.z && basis == o.basis;
        }
    };
    static Key keyOf(const DrawItem& item, const dvec3& eye);

private:
    struct KeyHash {
        size_t operator()(const Key& k) const;
    };
    unsigned program_ = 0, vao_ = 0, vertices_ = 0, indices_ = 0;
    int uViewProj_ = -1;
    size_t indexCapacity_ = 0;                     // boxes the index buffer holds
    std::vector<unsigned> queries_;                // GL query names, reused frame to frame
    std::vector<Key> keys_;                        // this frame's queried items, by query
    std::vector<vec3> corners_;                    // their boxes, 8 eye-relative corners each
    std::vector<Key> pendingKeys_;                 // the queries issued and not read yet
    std::unordered_map<Key, bool, KeyHash> seen_;  // the last frame's results: any sample passed
    DrawList drawn_;
    Stats stats_;
};

}  // namespace sg
