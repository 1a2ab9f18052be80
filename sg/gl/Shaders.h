// The renderer's GLSL program: its two shaders' sources and the vertex attributes they read.
// Internal header: not installed (CMakeLists.txt, SGKIT_INTERNAL_HEADERS); its shape may change freely.
#pragma once
#include "sg/core/Math.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace sg {

// The one program that draws every item, each feature a uniform it branches on: what Renderer::ShaderMode::
// OneProgram draws with, and the reference its variants are tested against.
extern const char* const kVertexShader;
extern const char* const kFragmentShader;

// The features a draw uses; a variant is compiled for each combination drawn (Renderer::ShaderMode::Variants).
enum ShadeFeature : uint32_t {
    kShadeTexture = 1u << 0,   // the material's texture, over UVs
    kShadeColor = 1u << 1,     // vertex colours
    kShadeBaked = 1u << 2,     // Material::bakedLight: the vertex alpha is sun visibility (with kShadeColor)
    kShadeLit = 1u << 3,       // lit: normals, and a material that is not unlit
    kShadeSun = 1u << 4,       // by the renderer's directional light (else the headlight)
    kShadeSpecular = 1u << 5,  // a Blinn-Phong highlight (with kShadeSun)
    kShadeAlphaCut = 1u << 6,  // Material::alphaCutoff above 0
    kShadeFade = 1u << 7,      // dissolving (an LOD's fade band)
};
// The features that change a variant's code: those that have no effect alone are dropped (baked light without
// vertex colours, light terms of an unlit draw, a highlight under the headlight).
uint32_t canonicalFeatures(uint32_t features);
// A variant's vertex or fragment source for these features.
std::string variantSource(bool vertex, uint32_t features);

// Per vertex, from a mesh's buffer (what the Mesh holds).
constexpr unsigned kPositionLocation = 0, kNormalLocation = 1, kUvLocation = 2, kColorLocation = 3;

// Per instance, from the frame's instance buffer: an item's matrix and base colour, at locations 4 to 8.
struct ItemAttributes {
    mat4 model{1.0f};
    vec4 baseColor{1.0f};
};

// In the bound vertex array: turns the item attributes on, one element per instance.
void enableItemAttributes();
// In the bound vertex array: the item attributes read the bound array buffer from its first'th element (GL 3.3
// has no base instance, so a run points them at its own first item).
void pointItemAttributes(size_t first);

}  // namespace sg
