// What the walks over a Scene's flat image (the cull, the intersection traversal) share: an entry's
// transform composed with its parent's, and the checks before a walk.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "sg/scene/ImageFrame.h"
#include "sg/scene/Scene.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

// parent * the transform of entry i (a Transform entry).
inline dmat4 transformed(const FlatImage& img, uint32_t i, const dmat4& parent) {
    return (img.flags[i] & FlatImage::kGeneral) ? parent * img.matrices[img.aux[i]]
                                                : mulTranslate(parent, img.translations[img.aux[i]]);
}

// Throws std::logic_error naming `fn` when the scene changed since its last update() (its image is stale);
// `choices`: a Switch turned counts too (the cull reads the image's copy of its bits, the intersection the node).
inline void checkUpdated(const Scene& scene, const char* fn, bool choices = false) {
    if ((scene.root()->dirtyBits() & (Node::kDirtyBound | Node::kDirtyBelow | Node::kDirtyStructure)) ||
        (choices && scene.root()->choiceChanged()))
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
