#include "nodes/Group.h"

#include "sg/NodeVisitor.h"

#include <stdexcept>

namespace sg {

Group::~Group() {
    for (auto& c : children_) c->removeParent(this);
}

void Group::checkChild(const Node* child, const char* fn) const {
    if (!child) throw std::invalid_argument(std::string(fn) + ": child is null (adding to " + describe() + ")");
    // A cycle appears exactly when this group is the child itself or lies below it.
    if (hasAncestorOrSelf(child))
        throw std::invalid_argument(std::string(fn) + ": adding " + child->describe() + " below " + describe() +
                                    " would make a cycle (the group is the child or one of its descendants)");
}

void Group::addChild(ref_ptr<Node> child) { insertChild(children_.size(), std::move(child)); }

void Group::insertChild(size_t index, ref_ptr<Node> child) {
    checkChild(child.get(), "Group::addChild()");
    if (index > children_.size()) index = children_.size();
    child->addParent(this);
    children_.insert(children_.begin() + static_cast<std::ptrdiff_t>(index), std::move(child));
    childInserted(index);
    markDirty(kDirtyStructure | kDirtyBound);
}

void Group::removeChild(size_t index) {
    if (index >= children_.size())
        throw std::out_of_range("Group::removeChild(): index " + std::to_string(index) + " past the " +
                                std::to_string(children_.size()) + " children of " + describe());
    children_[index]->removeParent(this);
    children_.erase(children_.begin() + static_cast<std::ptrdiff_t>(index));
    childRemoved(index);
    markDirty(kDirtyStructure | kDirtyBound);
}

bool Group::removeChild(const Node* c) {
    const size_t i = indexOf(c);
    if (i == children_.size()) return false;
    removeChild(i);
    return true;
}

void Group::removeAllChildren() {
    while (!children_.empty()) removeChild(children_.size() - 1);
}

size_t Group::indexOf(const Node* c) const noexcept {
    for (size_t i = 0; i < children_.size(); ++i)
        if (children_[i].get() == c) return i;
    return children_.size();
}

void Group::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
