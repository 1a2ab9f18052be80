#include "nodes/Transform.h"

#include "sg/core/NodeVisitor.h"

#include <stdexcept>

namespace sg {

void Transform::setMatrix(const dmat4& m) {
    const std::string bad = nonFiniteElement(m);
    if (!bad.empty()) throw std::invalid_argument("Transform::setMatrix(): " + describe() + ": " + bad);
    const std::string proj = nonAffineRow(m);
    if (!proj.empty()) throw std::invalid_argument("Transform::setMatrix(): " + describe() + ": " + proj);
    const double det = glm::determinant(glm::dmat3(m));
    const double scale = glm::length(dvec3(m[0])) * glm::length(dvec3(m[1])) * glm::length(dvec3(m[2]));
    if (!(std::abs(det) > eps::kDegenerate * scale) || scale == 0.0)
        throw std::invalid_argument("Transform::setMatrix(): " + describe() + ": matrix is singular (det " +
                                    std::to_string(det) + ") " + toString(m));
    if (sg::isTranslation(m)) {
        general_.reset();
        translation_ = dvec3(m[3]);
    } else {
        general_ = std::make_unique<dmat4>(m);
        translation_ = dvec3(m[3]);
    }
    markDirty(kDirtyBound);
}

void Transform::setTranslation(const dvec3& t) {
    if (!isFinite(t))
        throw std::invalid_argument("Transform::setTranslation(): " + describe() + ": translation is not finite");
    if (general_) {
        (*general_)[3] = dvec4(t, (*general_)[3].w);
    }
    translation_ = t;
    markDirty(kDirtyBound);
}

void Transform::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
