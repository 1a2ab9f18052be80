#include "nodes/Group.h"

#include "sg/core/NodeVisitor.h"

#include <algorithm>
#include <stdexcept>

namespace sg {

Group::~Group() {
    Node* const* d = data();
    for (uint32_t i = 0; i < size_; ++i) {
        d[i]->removeParent(this);
        d[i]->unref();
    }
    if (capLog2_) delete[] many_;
}

void Group::checkChild(const Node* child, const char* fn) const {
    if (!child) throw std::invalid_argument(std::string(fn) + ": child is null (adding to " + describe() + ")");
    // A cycle appears exactly when this group is the child itself or lies below it.
    if (hasAncestorOrSelf(child))
        throw std::invalid_argument(std::string(fn) + ": adding " + child->describe() + " below " + describe() +
                                    " would make a cycle (the group is the child or one of its descendants)");
}

void Group::addChild(ref_ptr<Node> child) { insertAt(size_, std::move(child), "Group::addChild()"); }

void Group::insertChild(size_t index, ref_ptr<Node> child) {
    insertAt(index, std::move(child), "Group::insertChild()");
}

void Group::insertAt(size_t index, ref_ptr<Node> child, const char* fn) {
    checkChild(child.get(), fn);
    if (index > size_) index = size_;
    if (size_ == capacity()) {  // grow: 1 (inline) -> 2 -> 4 ... on the heap
        if (capLog2_ >= 31) throw std::length_error(std::string(fn) + ": " + describe() + " has too many children");
        Node** d = new Node*[size_t(capacity()) * 2];
        std::copy(data(), data() + size_, d);
        if (capLog2_) delete[] many_;
        many_ = d;
        ++capLog2_;
    }
    Node** d = capLog2_ == 0 ? &one_ : many_;
    std::copy_backward(d + index, d + size_, d + size_ + 1);
    child->addParent(this);
    child->ref();
    d[index] = child.get();
    ++size_;
    childInserted(index);
    markDirty(childChangeMarks(child.get()));
}

void Group::removeChild(size_t index) {
    if (index >= size_)
        throw std::out_of_range("Group::removeChild(): index " + std::to_string(index) + " past the " +
                                std::to_string(size_) + " children of " + describe());
    Node** d = capLog2_ == 0 ? &one_ : many_;
    Node* c = d[index];
    const uint8_t marks = childChangeMarks(c);
    std::copy(d + index + 1, d + size_, d + index);
    --size_;
    c->removeParent(this);
    childRemoved(index);
    markDirty(marks);
    c->unref();  // last: the child may go away here
}

bool Group::removeChild(const Node* c) {
    const size_t i = indexOf(c);
    if (i == size_) return false;
    removeChild(i);
    return true;
}

void Group::removeAllChildren() {
    while (size_) removeChild(size_ - 1);
}

size_t Group::indexOf(const Node* c) const noexcept {
    for (size_t i = 0; i < size_; ++i)
        if (data()[i] == c) return i;
    return size_;
}

void Group::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
