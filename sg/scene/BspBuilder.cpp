#include "sg/scene/internal/BspBuilder.h"

#include <algorithm>

namespace sg {

namespace {
struct Build {
    const std::vector<Box>& boxes;
    std::vector<BspGroup::BspNode> nodes;
    std::vector<uint32_t> items;

    int32_t make(std::vector<uint32_t> set) {
        const int32_t id = int32_t(nodes.size());
        nodes.emplace_back();
        Box cb;  // box of the centres
        for (uint32_t k : set) cb.expand(boxes[k].center());
        const dvec3 ext = cb.max - cb.min;
        const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        std::vector<uint32_t> front, back, on;
        double split = 0.0;
        if (set.size() > 1 && ext[axis] > 0.0) {
            // Median by centre; where the two halves do not overlap, split in the gap between them so
            // that no child straddles the plane.
            std::sort(set.begin(), set.end(),
                      [&](uint32_t a, uint32_t b) { return boxes[a].center()[axis] < boxes[b].center()[axis]; });
            const size_t half = set.size() / 2;
            double leftMax = -kInf, rightMin = kInf;
            for (size_t k = 0; k < set.size(); ++k)
                if (k < half)
                    leftMax = std::max(leftMax, boxes[set[k]].max[axis]);
                else
                    rightMin = std::min(rightMin, boxes[set[k]].min[axis]);
            split = leftMax <= rightMin ? 0.5 * (leftMax + rightMin) : boxes[set[half]].center()[axis];
            for (uint32_t k : set) {
                if (boxes[k].min[axis] >= split)
                    front.push_back(k);
                else if (boxes[k].max[axis] <= split)
                    back.push_back(k);
                else
                    on.push_back(k);
            }
            if (front.empty() && back.empty()) on = set;  // nothing separates: keep them here
        } else {
            on = set;
        }
        dvec3 n(0.0);
        n[axis] = 1.0;
        nodes[size_t(id)].plane = Plane{n, -split};
        nodes[size_t(id)].firstItem = uint32_t(items.size());
        nodes[size_t(id)].itemCount = uint32_t(on.size());
        items.insert(items.end(), on.begin(), on.end());
        if (on.size() != set.size()) {
            const int32_t f = front.empty() ? -1 : make(std::move(front));
            const int32_t b = back.empty() ? -1 : make(std::move(back));
            nodes[size_t(id)].front = f;
            nodes[size_t(id)].back = b;
        }
        return id;
    }
};
}  // namespace

void buildBsp(BspGroup& group, const std::vector<Box>& childBoxes) {
    Build b{childBoxes, {}, {}};
    std::vector<uint32_t> all;
    for (uint32_t k = 0; k < childBoxes.size(); ++k)
        if (!childBoxes[k].empty())
            all.push_back(k);
        else
            b.items.push_back(k);  // empty children: order does not matter, visit first
    const uint32_t emptyCount = uint32_t(b.items.size());
    if (!all.empty()) b.make(std::move(all));
    if (emptyCount && !b.nodes.empty()) {
        // The root was made first, so its own items follow the empty children directly: widen its range.
        b.nodes[0].firstItem = 0;
        b.nodes[0].itemCount += emptyCount;
    } else if (emptyCount) {
        BspGroup::BspNode leaf;
        leaf.itemCount = emptyCount;
        b.nodes.push_back(leaf);
    }
    group.setBsp(std::move(b.nodes), std::move(b.items));
}

}  // namespace sg
