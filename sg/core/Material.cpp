#include "sg/core/Material.h"

#include <atomic>
#include <stdexcept>
#include <string>

namespace sg {

static std::atomic<uint32_t> g_nextMaterialId{1};

Texture::Texture(int width, int height, std::vector<uint8_t> rgba) : w_(width), h_(height), rgba_(std::move(rgba)) {
    if (width <= 0 || height <= 0 || rgba_.size() != size_t(width) * size_t(height) * 4)
        throw std::invalid_argument("Texture::Texture(): " + std::to_string(width) + "x" + std::to_string(height) +
                                    " needs " +
                                    std::to_string(size_t(std::max(width, 0)) * size_t(std::max(height, 0)) * 4) +
                                    " bytes, got " + std::to_string(rgba_.size()));
}

Material::Material(const vec4& c, ref_ptr<Texture> tex)
    : baseColor(c), texture(std::move(tex)), id_(g_nextMaterialId++) {}

ref_ptr<Material> Material::copy() const {
    ref_ptr<Material> c(new Material(*this));  // every field, the reference count not (Referenced's copy)
    c->id_ = g_nextMaterialId++;
    return c;
}

}  // namespace sg
