// Group: a node with an ordered list of children; the base of every node that has children.
#pragma once
#include "sg/Node.h"

#include <vector>

namespace sg {

class Group : public Node {
public:
    Group() : Node(NodeKind::Group) {}

    // Adds `child` last. Throws std::invalid_argument for a null child or one that would make a cycle.
    void addChild(ref_ptr<Node> child);
    void insertChild(size_t index, ref_ptr<Node> child);
    // Removes the child at `index`; throws std::out_of_range past the end.
    void removeChild(size_t index);
    bool removeChild(const Node* child);
    void removeAllChildren();

    size_t numChildren() const noexcept override { return children_.size(); }
    Node* child(size_t i) const noexcept override { return i < children_.size() ? children_[i].get() : nullptr; }
    // Index of `c` among the children, or numChildren() when absent.
    size_t indexOf(const Node* c) const noexcept;

    void accept(NodeVisitor& v) override;

protected:
    explicit Group(NodeKind k) : Node(k) {}
    ~Group() override;
    // Hook for nodes that keep per-child data (LOD ranges, Switch bits).
    virtual void childInserted(size_t) {}
    virtual void childRemoved(size_t) {}
    const char* addChildName() const;

private:
    void checkChild(const Node* child, const char* fn) const;
    std::vector<ref_ptr<Node>> children_;
};

}  // namespace sg
