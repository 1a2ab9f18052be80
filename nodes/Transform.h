// Transform: places its children with a double-precision affine matrix.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Math.h"

#include <memory>

namespace sg {

class Transform : public Group {
public:
    Transform() : Group(NodeKind::Transform) {}
    explicit Transform(const dmat4& m) : Transform() { setMatrix(m); }

    // Throws std::invalid_argument naming the element when the matrix has a NaN or infinity, when its
    // upper 3x3 is singular (bounds and picking need an invertible matrix), or when it is projective.
    void setMatrix(const dmat4& m);
    void setTranslation(const dvec3& t);
    dmat4 matrix() const { return general_ ? *general_ : glm::translate(dmat4(1.0), translation_); }
    bool isTranslation() const noexcept { return !general_; }
    // The full matrix when it is not a translation, else null (stable until the next set).
    const dmat4* matrixPtr() const noexcept { return general_.get(); }
    const dvec3& translation() const noexcept { return translation_; }
    // parent * this matrix, with the cheap path for translations.
    dmat4 apply(const dmat4& parent) const {
        return general_ ? parent * *general_ : mulTranslate(parent, translation_);
    }

    void accept(NodeVisitor& v) override;

private:
    // Most transforms in a walkthrough place objects: a translation is kept as 3 doubles, and the full
    // matrix lives out of line only when needed. This keeps large scenes within their memory budget.
    dvec3 translation_{0.0};
    std::unique_ptr<dmat4> general_;
};

}  // namespace sg
