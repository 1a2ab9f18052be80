// PickSet: the nodes an application counts as objects (a map's regions of the current level); a pick
// walks the hit's node path upward to the first of them. Also the ray through a window pixel.
#pragma once
#include "sg/core/Camera.h"
#include "sg/intersect/IntersectTraversal.h"

#include <string>
#include <unordered_map>

namespace sg {

// The segment through window pixel (x, y) (x to the right, y down, pixel centres at +0.5) from the near to
// the far plane: what is drawn at that pixel lies on it. Throws std::invalid_argument for non-finite x, y.
Ray pixelRay(const Camera& camera, double x, double y);

// A hit's node path as one line, root first: "Group 'office' / Group 'room 3' / Transform / Geometry" (for
// viewers that print what was clicked).
std::string pathString(const std::vector<Node*>& path);

class PickSet {
public:
    // Throws std::invalid_argument for a null node. The set holds a reference to each node.
    void add(Node* node);
    bool remove(const Node* node);
    void clear() { nodes_.clear(); }
    bool contains(const Node* node) const { return nodes_.count(node) != 0; }
    size_t size() const { return nodes_.size(); }

    // The registered node nearest the geometry on `path` (root first), or null.
    Node* resolve(const std::vector<Node*>& path) const;

    struct Result {
        Node* object = nullptr;  // null when the hit is on no registered node, or nothing was hit
        bool hit = false;
        Hit nearest;  // the nearest pickable hit (valid when `hit`)
    };
    // Picks at window pixel (x, y) through the camera: LOD levels as that camera draws them (unless
    // options say otherwise), billboards facing it, kPickable nodes (options.traversalMask).
    Result pick(IntersectTraversal& traversal, const Scene& scene, const Camera& camera, double x, double y,
                QueryOptions options = {}) const;

private:
    std::unordered_map<const Node*, ref_ptr<Node>> nodes_;
};

}  // namespace sg
