// Posed Geometries in the image: an entry's pose made and kept (FlatImage::posed) with the bound it gives, the skinned
// Geometries listed for the update, and the update's check of which of them had a joint moved.
#include "sg/scene/Posing.h"
#include "sg/scene/internal/ImageBounds.h"
#include "sg/scene/internal/ImageBuilder.h"

#include <algorithm>
#include <stdexcept>

namespace sg {

namespace {
using PoseEntry = std::pair<uint32_t, ref_ptr<const Pose>>;

std::vector<PoseEntry>::iterator findPose(std::vector<PoseEntry>& v, uint32_t i) {
    return std::lower_bound(v.begin(), v.end(), i, [](const PoseEntry& e, uint32_t k) { return e.first < k; });
}
}  // namespace

// Entry i of posed Geometry g: its pose made anew (lending the last one's morphed mesh) and its bound. A skinned
// pose's box is a world box: where g sits places nothing (m is not used).
void Scene::Builder::posed(uint32_t i, Geometry* g, const dmat4& m) {
    std::vector<PoseEntry>& v = img.posed;
    // A full build writes its entries in order (appended); a refit rewrites an entry's pose where it is.
    auto it = fresh ? v.end() : findPose(v, i);
    const bool present = it != v.end() && it->first == i;
    const Pose* had = present ? it->second.get() : nullptr;
    ref_ptr<const Pose> pose = makePose(*g, had);
    if (!detail) noteSkinned(g, had);
    const Pose& p = *pose;  // held by the table from here on
    if (present)
        it->second = std::move(pose);
    else
        v.insert(it, {i, std::move(pose)});
    img.flags[i] |= FlatImage::kPosed;
    if (!p.skinned()) return leafBound(i, p.box, p.drawn(*g->mesh()).validBound(), m);
    if (p.box.empty()) return img.setBound(i, Box{}, 0.0);
    if (!isFinite(p.box.min) || !isFinite(p.box.max)) return img.setInvalid(i);
    img.setBound(i, p.box, glm::length(p.box.halfExtent()));
}

// Entry i is no longer posed (its Geometry lost its skin and weights): its pose leaves the table.
void Scene::Builder::dropPose(uint32_t i) {
    if (fresh || img.posed.empty()) return;
    auto it = findPose(img.posed, i);
    if (it != img.posed.end() && it->first == i) img.posed.erase(it);
}

// A skinned Geometry listed for the update's check (markMovedSkins). A full build lists every one it meets; a later
// write lists one that was not skinned when last written (given its skin since). A joint that holds g below it would
// make each pose move the joints' paths again: refused.
void Scene::Builder::noteSkinned(Geometry* g, const Pose* had) {
    const Skin* skin = g->skin();
    if (!skin || (!collect && had && had->skinned())) return;
    for (const ref_ptr<Node>& joint : skin->joints())
        if (g->hasAncestorOrSelf(joint.get()))
            throw std::invalid_argument("Scene::update(): " + joint->describe() + " is a joint of " + g->describe() +
                                        "'s skin and holds it below: put skinned Geometries beside their skeleton");
    std::vector<Geometry*>& list = scene.skinned_;
    if (collect || std::find(list.begin(), list.end(), g) == list.end()) list.push_back(g);
}

// Marks kDirtyBound on each listed skinned Geometry whose pose moved with a joint: a joint changed itself or below
// it, or a node above the first joint changed (the skeleton's root usually; its other joints hang below it).
void Scene::markMovedSkins() {
    constexpr uint8_t kMoved = Node::kDirtyBound | Node::kDirtyBelow;
    for (Geometry* g : skinned_) {
        const Skin* skin = g->skin();
        if (!skin || (g->dirtyBits() & Node::kDirtyBound)) continue;
        bool moved = std::any_of(skin->joints().begin(), skin->joints().end(),
                                 [](const ref_ptr<Node>& j) { return (j->dirtyBits() & kMoved) != 0; });
        const Node* first = skin->joints()[0].get();
        for (const Node* a = first->numParents() ? first->parent(0) : nullptr; a && !moved;
             a = a->numParents() ? a->parent(0) : nullptr)
            moved = (a->dirtyBits() & Node::kDirtyBound) != 0;
        if (moved) g->markDirty(Node::kDirtyBound);
    }
}

}  // namespace sg
