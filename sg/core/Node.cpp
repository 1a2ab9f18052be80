#include "sg/core/Node.h"

#include "sg/core/Features.h"
#include "sg/core/NodeVisitor.h"

#include <algorithm>

namespace sg {

struct Node::Extras {
    Node* firstParent = nullptr;
    std::string name;
    UpdateCallback callback;
    std::vector<Node*> moreParents;  // parents after the first (DAG)
    ref_ptr<const MeshFeatures> features;
    uint32_t featureIndex = 0;
};

const char* kindName(NodeKind k) {
    switch (k) {
        case NodeKind::Group: return "Group";
        case NodeKind::Transform: return "Transform";
        case NodeKind::Geometry: return "Geometry";
        case NodeKind::LOD: return "LOD";
        case NodeKind::Switch: return "Switch";
        case NodeKind::Billboard: return "Billboard";
        case NodeKind::Instance: return "Instance";
        case NodeKind::BspGroup: return "BspGroup";
        case NodeKind::Occluder: return "Occluder";
        case NodeKind::PagedLOD: return "PagedLOD";
    }
    return "Node";
}

Node::~Node() {
    if (state_ & kHasExtras) delete extras_;
}

Node::Extras& Node::extras() {
    if (!(state_ & kHasExtras)) {
        auto* e = new Extras;
        e->firstParent = firstParent_;
        extras_ = e;
        state_ |= kHasExtras;
    }
    return *extras_;
}

Node* Node::firstParent() const noexcept { return state_ & kHasExtras ? extras_->firstParent : firstParent_; }

void Node::setFirstParent(Node* p) noexcept {
    if (state_ & kHasExtras)
        extras_->firstParent = p;
    else
        firstParent_ = p;
}

void Node::setNodeMask(uint32_t m) {
    mask_ = m;
    if (m == 0xffffffffu)
        state_ &= ~kHasMask;
    else
        state_ |= kHasMask;
    markDirty(kDirtyBound);  // the image caches whether a mask must be read
}

const std::string& Node::name() const {
    static const std::string empty;
    const Extras* e = findExtras();
    return e ? e->name : empty;
}

void Node::setName(std::string name) { extras().name = std::move(name); }

void Node::setFeatures(ref_ptr<const MeshFeatures> features, uint32_t index) {
    Extras& e = extras();
    e.features = std::move(features);
    e.featureIndex = index;
    markDirty(kDirtyBound);  // the image holds a copy
}

const MeshFeatures* Node::features() const {
    const Extras* e = findExtras();
    return e ? e->features.get() : nullptr;
}

uint32_t Node::featureIndex() const {
    const Extras* e = findExtras();
    return e ? e->featureIndex : 0;
}

std::string Node::describe() const {
    std::string s = kindName();
    if (!name().empty()) s += " '" + name() + "'";
    return s;
}

void Node::setUpdateCallback(UpdateCallback cb) {
    extras().callback = std::move(cb);
    markDirty(kDirtyStructure);  // the image keeps the list of nodes with callbacks
}

const UpdateCallback* Node::updateCallback() const {
    const Extras* e = findExtras();
    return e && e->callback ? &e->callback : nullptr;
}

size_t Node::numParents() const noexcept {
    if (!firstParent()) return 0;
    const Extras* e = findExtras();
    return 1 + (e ? e->moreParents.size() : 0);
}

Node* Node::parent(size_t i) const noexcept {
    if (i == 0) return firstParent();
    const Extras* e = findExtras();
    return e && i - 1 < e->moreParents.size() ? e->moreParents[i - 1] : nullptr;
}

void Node::addParent(Node* p) {
    if (!firstParent())
        setFirstParent(p);
    else
        extras().moreParents.push_back(p);
}

void Node::removeParent(Node* p) {
    Extras* e = (state_ & kHasExtras) ? extras_ : nullptr;
    if (firstParent() == p) {
        if (e && !e->moreParents.empty()) {
            setFirstParent(e->moreParents.back());
            e->moreParents.pop_back();
        } else {
            setFirstParent(nullptr);
        }
        return;
    }
    if (!e) return;
    auto& v = e->moreParents;
    // Swapped with the last, not erased: a prototype placed by thousands of Instances freed in the order they
    // were made loses its first parent each time, which erasing would make quadratic.
    auto it = std::find(v.begin(), v.end(), p);
    if (it == v.end()) return;
    *it = v.back();
    v.pop_back();
}

void Node::markDirty(uint8_t bits) {
    state_ |= bits;
    const uint8_t up = ((bits & (kDirtyBound | kDirtyBelow | kDirtyStructure)) ? kDirtyBelow : 0) |
                       (bits & (kDirtyStructure | kDirtyChoice));
    if (!up) return;
    // Up a chain of single parents (a tree: the common case, an animated joint's every frame) without a stack; stop
    // where the marks are already present (their ancestors have them).
    Node* a = this;
    while (a->numParents() == 1) {
        a = a->parent(0);
        if ((a->state_ & up) == up) return;
        a->state_ |= up;
    }
    // Several parents (a DAG): an iterative walk to the roots.
    std::vector<Node*> stack;
    for (size_t i = 0, n = a->numParents(); i < n; ++i) stack.push_back(a->parent(i));
    while (!stack.empty()) {
        Node* b = stack.back();
        stack.pop_back();
        if ((b->state_ & up) == up) continue;
        b->state_ |= up;
        for (size_t i = 0, n = b->numParents(); i < n; ++i) stack.push_back(b->parent(i));
    }
}

bool Node::hasAncestorOrSelf(const Node* n) const {
    std::vector<const Node*> stack{this};
    std::vector<const Node*> seen;
    while (!stack.empty()) {
        const Node* a = stack.back();
        stack.pop_back();
        if (a == n) return true;
        if (a->numParents() > 1) {  // only DAG joins can be reached twice
            if (std::find(seen.begin(), seen.end(), a) != seen.end()) continue;
            seen.push_back(a);
        }
        for (size_t i = 0, k = a->numParents(); i < k; ++i) stack.push_back(a->parent(i));
    }
    return false;
}

void Node::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
