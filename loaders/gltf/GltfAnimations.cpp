// glTF animations as sg::Animations bound to the nodes built from the file.
#include "loaders/gltf/internal/GltfConverter.h"

namespace sg::gltf {

void Converter::animations() {
    if (!m.animations.empty()) warn("animations", "animations are not loaded");
}

}  // namespace sg::gltf
