// Feature ID look-ups (sg/core/Features.h): a vertex's, an instance's or a texel's feature, and a texture's texel.
#include "sg/core/Features.h"

#include <algorithm>
#include <cmath>

namespace sg {

namespace {

int64_t unlessNull(const FeatureIdSet& s, uint64_t id) {
    return s.hasNullFeatureId && id == s.nullFeatureId ? -1 : int64_t(id);
}

// The texel index along one axis of `size` texels: REPEAT wrapping, nearest texel.
int texelIndex(float t, int size) {
    if (!std::isfinite(t)) t = 0.0f;
    const double f = double(t) - std::floor(double(t));  // fract, in [0, 1]
    return std::clamp(int(std::floor(f * size)), 0, size - 1);
}

}  // namespace

int64_t MeshFeatures::idAt(size_t set, size_t i) const {
    if (set >= sets.size()) return -1;
    const FeatureIdSet& s = sets[set];
    switch (s.source) {
        case FeatureIdSet::Source::Attribute:
        case FeatureIdSet::Source::Instance: return i < s.ids.size() ? unlessNull(s, s.ids[i]) : -1;
        case FeatureIdSet::Source::Implicit:
            // A featureCount of 0 is one the file did not give: then any index is an id.
            if (s.featureCount > 0 && i >= s.featureCount) return -1;
            return unlessNull(s, i);
        case FeatureIdSet::Source::Texture: return -1;
    }
    return -1;
}

int64_t MeshFeatures::idAtUv(size_t set, const vec2& uv) const {
    if (set >= sets.size()) return -1;
    const FeatureIdSet& s = sets[set];
    if (s.source != FeatureIdSet::Source::Texture || !s.texture || s.channels.empty()) return -1;
    const std::vector<uint8_t> bytes = texelChannels(*s.texture, uv, s.channels);
    uint64_t id = 0;
    for (size_t k = 0; k < bytes.size() && k < 8; ++k) id |= uint64_t(bytes[k]) << (8 * k);  // little-endian
    return unlessNull(s, id);
}

size_t MeshFeatures::bytes() const {
    // The store and the textures are shared with other meshes: not counted here.
    size_t n = sizeof(*this) + sets.capacity() * sizeof(FeatureIdSet) + propertyTextures.capacity() * sizeof(int);
    for (const FeatureIdSet& s : sets)
        n += s.label.capacity() + s.ids.capacity() * sizeof(uint32_t) + s.channels.capacity();
    for (const PropertyAttributeValues& a : propertyAttributes) {
        n += sizeof(a) + a.columns.capacity() * sizeof(PropertyAttributeValues::Column);
        for (const auto& c : a.columns) n += c.bytes.capacity();
    }
    return n;
}

std::vector<uint8_t> texelChannels(const Texture& texture, const vec2& uv, const std::vector<uint8_t>& channels) {
    std::vector<uint8_t> out;
    const int w = texture.width(), h = texture.height();
    if (w <= 0 || h <= 0 || texture.rgba().size() < size_t(w) * size_t(h) * 4) return out;
    // glTF's UV origin is the image's top-left corner, and a Texture's rows are stored top row first (as the glTF
    // loader decodes them, loaders/gltf/GltfMaterials.cpp): v indexes the rows directly, no flip.
    const size_t x = size_t(texelIndex(uv.x, w)), y = size_t(texelIndex(uv.y, h));
    const uint8_t* texel = texture.rgba().data() + (y * size_t(w) + x) * 4;
    out.reserve(channels.size());
    for (uint8_t c : channels) out.push_back(c < 4 ? texel[c] : 0);
    return out;
}

}  // namespace sg
