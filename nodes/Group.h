// Group: a node with an ordered list of children; the base of every node that has children.
#pragma once
#include "sg/core/Node.h"

namespace sg {

class Group : public Node {
public:
    Group() : Node(NodeKind::Group), one_(nullptr) {}

    // Adds `child` last. Throws std::invalid_argument for a null child or one that would make a cycle.
    void addChild(ref_ptr<Node> child);
    void insertChild(size_t index, ref_ptr<Node> child);
    // Removes the child at `index`; throws std::out_of_range past the end.
    void removeChild(size_t index);
    bool removeChild(const Node* child);
    void removeAllChildren();

    size_t numChildren() const noexcept override { return size_; }
    Node* child(size_t i) const noexcept override { return i < size_ ? data()[i] : nullptr; }
    // Index of `c` among the children, or numChildren() when absent.
    size_t indexOf(const Node* c) const noexcept;

    void accept(NodeVisitor& v) override;

protected:
    explicit Group(NodeKind k) : Node(k), one_(nullptr) {}
    ~Group() override;
    // Hook for nodes that keep per-child data (LOD ranges, Switch bits).
    virtual void childInserted(size_t) {}
    virtual void childRemoved(size_t) {}
    // The dirty marks that adding or removing `child` makes: a structural change, unless the node keeps that
    // child out of the scene's image (a PagedLOD's detail has an image of its own).
    virtual uint8_t childChangeMarks(const Node*) const { return kDirtyStructure | kDirtyBound; }

private:
    void checkChild(const Node* child, const char* fn) const;
    // addChild() and insertChild(); `fn` names the one called in error messages.
    void insertAt(size_t index, ref_ptr<Node> child, const char* fn);
    Node* const* data() const noexcept { return capLog2_ == 0 ? &one_ : many_; }
    uint32_t capacity() const noexcept { return 1u << capLog2_; }
    // Children hold a reference each. One child is kept inline (most transforms hold exactly one), more
    // in a heap array. The counts come first so that they fill the tail of Node: a Group is 40 bytes.
    uint8_t capLog2_ = 0;
    uint32_t size_ = 0;
    union {
        Node* one_;
        Node** many_;
    };
};

}  // namespace sg
