// Instance: places a shared prototype subgraph with its own matrix; the prototype is stored (and its
// flat image built) once however often it is placed, and every placement is culled on its own.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Node.h"

namespace sg {

class Instance : public Node {
public:
    Instance() : Node(NodeKind::Instance) {}
    Instance(ref_ptr<Node> prototype, const dmat4& placement) : Instance() {
        setPrototype(std::move(prototype));
        setMatrix(placement);
    }
    ~Instance() override;
    // Throws std::invalid_argument for a null prototype or one that would make a cycle.
    void setPrototype(ref_ptr<Node> p);
    Node* prototype() const noexcept { return proto_.get(); }
    // Throws std::invalid_argument with nonInvertibleAffine()'s reason (non-finite, projective, singular).
    void setMatrix(const dmat4& m);
    const dmat4& matrix() const noexcept { return matrix_; }

    size_t numChildren() const noexcept override { return proto_ ? 1 : 0; }
    Node* child(size_t i) const noexcept override { return i == 0 ? proto_.get() : nullptr; }
    void accept(NodeVisitor& v) override;

private:
    ref_ptr<Node> proto_;
    dmat4 matrix_{1.0};
};

}  // namespace sg
