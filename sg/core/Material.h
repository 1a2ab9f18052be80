// Material: base colour, an optional RGBA8 texture and how light meets the surface; shared between geometries.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Ref.h"

#include <cstdint>
#include <vector>

namespace sg {

// How a texture is read between and beyond its texels (glTF's samplers): wrapping per axis and the filters. Mipmaps
// are made for every texture; a min filter without "Mipmap" reads only the top level. The renderer keeps one GL
// sampler object per distinct Sampler.
struct Sampler {
    enum class Wrap : uint8_t { Repeat, MirroredRepeat, ClampToEdge };
    enum class Filter : uint8_t {
        Nearest,
        Linear,
        NearestMipmapNearest,
        LinearMipmapNearest,
        NearestMipmapLinear,
        LinearMipmapLinear,
    };
    Wrap wrapS = Wrap::Repeat, wrapT = Wrap::Repeat;
    Filter magFilter = Filter::Linear;  // Nearest or Linear only
    Filter minFilter = Filter::LinearMipmapLinear;
    bool operator==(const Sampler& o) const {
        return wrapS == o.wrapS && wrapT == o.wrapT && magFilter == o.magFilter && minFilter == o.minFilter;
    }
    bool operator!=(const Sampler& o) const { return !(*this == o); }
};

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
    // How it is sampled (the default: repeat, trilinear). Set before the texture is first drawn.
    Sampler sampler;

private:
    int w_, h_;
    std::vector<uint8_t> rgba_;
};

// A texture as a material uses it: which of the mesh's UV sets it reads (0: Mesh::uvs(), 1: Mesh::uvs1()) and the
// transform applied to those UVs first (KHR_texture_transform: translation * rotation * scale, as a 3x3 matrix).
struct TextureSlot {
    ref_ptr<Texture> texture;
    int texCoord = 0;
    mat3 transform{1.0f};
};

// glTF 2.0's metallic-roughness model (its Appendix B): what Material::physical shades with. Textures multiply
// their factors; colour textures (base colour, emissive) hold sRGB values, the others linear ones.
struct PhysicalMaterial {
    float metallic = 1.0f, roughness = 1.0f;
    TextureSlot metallicRoughness;  // roughness in G, metallic in B
    TextureSlot normal;             // tangent space; needs Mesh::tangents()
    float normalScale = 1.0f;
    TextureSlot occlusion;  // in R, applied to the environment light only
    float occlusionStrength = 1.0f;
    TextureSlot emissive;
    vec3 emissiveFactor{0.0f};  // linear; KHR_materials_emissive_strength already multiplied in
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

    // Shaded by the metallic-roughness model (glTF's materials) instead of the classic terms above: base colour
    // and vertex colours are linear, the texture sRGB, the light the renderer's sun or headlight plus a sky and
    // ground hemisphere (Renderer::setLight), and the result written as sRGB. `unlit` then writes the base colour
    // alone (KHR_materials_unlit); specular, shininess and bakedLight are not used.
    bool physical = false;
    PhysicalMaterial pbr;
    int texCoord = 0;             // the UV set `texture` reads (physical materials only)
    mat3 textureTransform{1.0f};  // applied to those UVs first (physical materials only)
    // Blended over what is behind it by its alpha (glTF's alphaMode BLEND): drawn after the opaque items, back to
    // front, with depth writes off. Such geometry never hides anything, so no occlusion test may treat it as
    // an occluder.
    bool blend = false;
    // Both sides drawn (sgkit's materials). false: back faces are not drawn (glTF's default, doubleSided false).
    bool doubleSided = true;

    uint32_t id() const { return id_; }
    // A copy with every setting of this one and an id of its own: what replaces a material that frames in flight
    // may still draw (an animated property, a style) without touching it.
    ref_ptr<Material> copy() const;

private:
    uint32_t id_;
};

}  // namespace sg
