// What the walks over a Scene's flat image (the cull, the intersection traversal) share: an entry's
// transform composed with its parent's, whether a frame keeps lengths, and the checks before a walk.
// Internal header: not installed (CMakeLists.txt, SGKIT_INTERNAL_HEADERS); its shape may change freely.
#pragma once
#include "sg/scene/Scene.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

// parent * the transform of entry i (a Transform entry).
inline dmat4 transformed(const FlatImage& img, uint32_t i, const dmat4& parent) {
    return (img.flags[i] & FlatImage::kGeneral) ? parent * *img.matrices[img.aux[i]]
                                                : mulTranslate(parent, img.translations[img.aux[i]]);
}

// Whether `t` keeps lengths (A^T A == I within eps::kRigid for its linear part A): distances may then be taken in
// the frame it maps from.
inline bool isRigid(const dmat4& t) {
    const glm::dmat3 a(t);
    const glm::dmat3 ata = glm::transpose(a) * a;
    return glm::length(ata[0] - dvec3(1, 0, 0)) + glm::length(ata[1] - dvec3(0, 1, 0)) +
               glm::length(ata[2] - dvec3(0, 0, 1)) <
           eps::kRigid;
}

// Throws std::logic_error naming `fn` when the scene changed since its last update() (its image is stale).
inline void checkUpdated(const Scene& scene, const char* fn) {
    if (scene.root()->dirtyBits() & (Node::kDirtyBound | Node::kDirtyBelow | Node::kDirtyStructure))
        throw std::logic_error(std::string(fn) +
                               ": the scene changed since its last update(); call Scene::update() first");
}

// Throws std::invalid_argument naming `fn` unless the LOD scale is positive and finite.
inline void checkLodScale(double lodScale, const char* fn) {
    if (!(lodScale > 0.0 && std::isfinite(lodScale)))
        throw std::invalid_argument(std::string(fn) + ": lodScale " + std::to_string(lodScale) +
                                    " is not a positive number");
}

}  // namespace sg
