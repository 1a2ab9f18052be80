// BspGroup: children visited front to back from the eye through a BSP tree over them, built by the
// update pass when they change (the scene order the occlusion passes rely on).
#pragma once
#include "nodes/Group.h"
#include "sg/core/Math.h"

#include <cstdint>
#include <vector>

namespace sg {

class BspGroup : public Group {
public:
    // One BSP node: a splitting plane in the group's frame; children straddling it are listed here and
    // visited between the near and the far side.
    struct BspNode {
        Plane plane;
        int32_t front = -1, back = -1;          // indices into nodes(), -1: none
        uint32_t firstItem = 0, itemCount = 0;  // range in items(): child indices on the plane
    };
    BspGroup() : Group(NodeKind::BspGroup) {}

    const std::vector<BspNode>& bspNodes() const { return nodes_; }
    const std::vector<uint32_t>& bspItems() const { return items_; }
    void setBsp(std::vector<BspNode> nodes, std::vector<uint32_t> items) {
        nodes_ = std::move(nodes);
        items_ = std::move(items);
    }
    // Child indices in front-to-back order for an eye at `eyeLocal` (the group's frame).
    void order(const dvec3& eyeLocal, std::vector<uint32_t>& out) const;

    void accept(NodeVisitor& v) override;

private:
    std::vector<BspNode> nodes_;  // built by the update pass (sg/BspBuilder)
    std::vector<uint32_t> items_;
};

}  // namespace sg
