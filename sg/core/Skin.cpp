#include "sg/core/Skin.h"

#include <cmath>
#include <stdexcept>

namespace sg {

Skin::Skin(std::vector<ref_ptr<Node>> joints, std::vector<dmat4> inverseBind)
    : joints_(std::move(joints)), inverseBind_(std::move(inverseBind)) {
    if (joints_.empty()) throw std::invalid_argument("Skin::Skin(): no joints");
    for (size_t i = 0; i < joints_.size(); ++i)
        if (!joints_[i]) throw std::invalid_argument("Skin::Skin(): joints[" + std::to_string(i) + "] is null");
    if (inverseBind_.empty()) inverseBind_.assign(joints_.size(), dmat4(1.0));
    if (inverseBind_.size() != joints_.size())
        throw std::invalid_argument("Skin::Skin(): " + std::to_string(inverseBind_.size()) +
                                    " inverse bind matrices for " + std::to_string(joints_.size()) + " joints");
    for (size_t i = 0; i < inverseBind_.size(); ++i) {
        const dmat4& m = inverseBind_[i];
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(m[c][r]))
                    throw std::invalid_argument("Skin::Skin(): inverseBind[" + std::to_string(i) + "][" +
                                                std::to_string(c) + "][" + std::to_string(r) + "] is not finite");
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
            throw std::invalid_argument("Skin::Skin(): inverseBind[" + std::to_string(i) +
                                        "] is not affine (its last row is not 0 0 0 1)");
    }
}

}  // namespace sg
