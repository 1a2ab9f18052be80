// Material: base colour, an optional RGBA8 texture and how light meets the surface; shared between geometries.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Ref.h"

#include <cstdint>
#include <vector>

namespace sg {

class Texture : public Referenced {
public:
    // Throws std::invalid_argument when the pixel count does not match width * height * 4.
    Texture(int width, int height, std::vector<uint8_t> rgba);
    int width() const { return w_; }
    int height() const { return h_; }
    const std::vector<uint8_t>& rgba() const { return rgba_; }
    // The most anisotropic filtering the renderer may use for it, where GL offers it cheaply (a GPU, not a
    // software rasterizer; 1: trilinear only): ground seen at grazing angles stays sharp without the cost
    // on textures that are never oblique.
    float maxAnisotropy = 1.0f;

private:
    int w_, h_;
    std::vector<uint8_t> rgba_;
};

class Material : public Referenced {
public:
    explicit Material(const vec4& baseColor = vec4(0.8f, 0.8f, 0.8f, 1.0f), ref_ptr<Texture> tex = {});
    vec4 baseColor;
    ref_ptr<Texture> texture;
    bool unlit = false;  // billboards and maps are often drawn without lighting
    // Fragments whose alpha (base colour x texture x vertex colour) is below this are discarded, the rest
    // drawn opaque: cut-out foliage and fences without sorting or blending. 0: off.
    float alphaCutoff = 0.0f;
    // Blinn-Phong highlight of a directional light: strength (0: none) and exponent. The headlight draws none.
    float specular = 0.0f;
    float shininess = 32.0f;
    // The vertex colours carry VertexLightBaker's output rather than plain colour: rgb the albedo times the
    // ambient occlusion, alpha the share of the sun that reaches the vertex (which dims the direct light only).
    bool bakedLight = false;
    uint32_t id() const { return id_; }

private:
    uint32_t id_;
};

}  // namespace sg
