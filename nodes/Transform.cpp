#include "nodes/Transform.h"

#include "sg/core/NodeVisitor.h"

#include <stdexcept>

namespace sg {

void Transform::setMatrix(const dmat4& m) {
    const std::string why = nonInvertibleAffine(m);
    if (!why.empty()) throw std::invalid_argument("Transform::setMatrix(): " + describe() + ": " + why);
    if (sg::isTranslation(m)) {
        general_.reset();
        translation_ = dvec3(m[3]);
    } else {
        if (general_)
            *general_ = m;  // an animated joint is set every frame: no allocation each time
        else
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
