// The Scene: its update pass (callbacks, then the image brought up to date by a Builder: internal/ImageBuilder.h).
#include "sg/scene/Scene.h"

#include "nodes/Geometry.h"
#include "nodes/Sequence.h"
#include "sg/scene/internal/ImageBuilder.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <unordered_set>

namespace sg {

Scene::Scene(ref_ptr<Node> root) : root_(std::move(root)) {
    if (!root_) throw std::invalid_argument("Scene::Scene(): root is null");
}

Scene::~Scene() = default;

const FlatImage* Scene::prototypeImage(const Node* p) const {
    auto it = protos_.find(p);
    return it == protos_.end() ? nullptr : it->second.get();
}

const FlatImage* Scene::prototypeImage(const FlatImage& placedIn, const Node* p) const {
    if (!placedIn.prototypes.empty()) {  // the scene's image and its prototypes' hold none: no hash for them
        auto it = placedIn.prototypes.find(p);
        if (it != placedIn.prototypes.end()) return it->second.get();
    }
    return prototypeImage(p);
}

void Scene::update(const FrameInfo& frame) {
    const auto t0 = std::chrono::steady_clock::now();
    stats_ = UpdateStats{};
    updates_++;
    frame_ = frame;
    // Structure first (it also finds the nodes with callbacks and the Sequences), then the Sequences and the
    // callbacks, then their changes.
    if ((root_->dirtyBits() & Node::kDirtyStructure) || main_.size() == 0) refresh();
    for (Sequence* q : sequences_) q->advance(frame.time);
    for (Node* n : callbacks_) {
        (*n->updateCallback())(*n, frame);
        stats_.callbacksRun++;
    }
    refresh();
    offers_.clear();  // images offered for details this update did not meet
    stats_.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::shared_ptr<FlatImage> Scene::buildDetailImage(Node& detail, const dmat4& frame) {
    Scene alone{ref_ptr<Node>(&detail)};  // its own draw states and stats: the adopting scene renumbers the states
    auto img = std::make_shared<FlatImage>();
    std::unordered_set<const Node*> built;
    Builder b{alone, *img, built};
    b.detail = true;  // its prototypes' images are its own: built here too
    b.full(&detail, frame);
    if (b.occludersWritten) b.occluderChunks();
    return img;
}

void Scene::offerDetailImage(const Node* paged, const Node* detail, const dmat4& frame,
                             std::shared_ptr<FlatImage> image) {
    if (paged && detail && image) offers_[paged] = Offer{detail, frame, std::move(image)};
}

void Scene::refresh() {
    // A joint moved: its skinned Geometries are re-posed by the refit (a full build poses every one anyway).
    if ((root_->dirtyBits() & (Node::kDirtyBound | Node::kDirtyBelow)) &&
        !(root_->dirtyBits() & Node::kDirtyStructure) && main_.size() != 0 && !skinned_.empty())
        markMovedSkins();
    const uint8_t bits = root_->dirtyBits() & (Node::kDirtyBound | Node::kDirtyBelow | Node::kDirtyStructure);
    if (bits || main_.size() == 0) {
        version_++;
        std::unordered_set<const Node*> built;
        Builder b{*this, main_, built};
        if ((bits & Node::kDirtyStructure) || main_.size() == 0) {
            callbacks_.clear();
            skinned_.clear();
            sequences_.clear();
            protos_.clear();
            b.collect = true;
            b.full(root_.get());
            structureVersion_++;
            // A shared node is met once per path: keep its first place in traversal order.
            std::unordered_set<const Node*> seen;
            callbacks_.erase(std::remove_if(callbacks_.begin(), callbacks_.end(),
                                            [&](const Node* n) { return !seen.insert(n).second; }),
                             callbacks_.end());
            seen.clear();
            skinned_.erase(
                std::remove_if(skinned_.begin(), skinned_.end(), [&](const Node* n) { return !seen.insert(n).second; }),
                skinned_.end());
            if (!sequences_.empty()) {
                seen.clear();
                sequences_.erase(std::remove_if(sequences_.begin(), sequences_.end(),
                                                [&](const Node* n) { return !seen.insert(n).second; }),
                                 sequences_.end());
            }
        } else {
            b.refit(0, root_.get(), dmat4(1.0));
            b.updateExtent();
        }
        if (b.occludersWritten) b.occluderChunks();
        // A Switch turned beside a refit that did not rewrite it (a full build wrote every switch's bits).
        if (!b.collect && root_->choiceChanged()) b.choices(0, root_.get());
        Builder::clear(root_.get());
    } else if (root_->choiceChanged()) {  // a Switch turned: its bits copied into the image, no refit
        version_++;
        std::unordered_set<const Node*> built;
        Builder b{*this, main_, built};
        b.choices(0, root_.get());
        Builder::clear(root_.get());
    }
}

size_t Scene::bytes() const {
    size_t b = main_.bytes();
    for (auto& p : protos_) b += p.second->bytes();
    return b;
}

}  // namespace sg
