// The renderer's GLSL program: its two shaders' sources and the vertex attributes they read.
// Internal header (an internal/ folder): not installed; its shape may change freely.
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
    // Material::physical: the metallic-roughness program (ShadersPbr.cpp), with kShadeTexture its base colour
    // texture, kShadeColor vertex colours, kShadeLit "not unlit", kShadeSun the sun (else the headlight) and
    // kShadeAlphaCut and kShadeFade as above, plus these:
    kShadePbr = 1u << 8,
    kShadePbrMr = 1u << 9,          // a metallic-roughness texture
    kShadePbrNormal = 1u << 10,     // a normal map (the mesh has tangents)
    kShadePbrOcclusion = 1u << 11,  // an occlusion texture
    kShadePbrEmissive = 1u << 12,   // an emissive texture
    kShadeUv0 = 1u << 13,           // a texture reads UV set 0
    kShadeUv1 = 1u << 14,           // a texture reads UV set 1
    kShadeFlat = 1u << 15,          // lit without vertex normals: the triangle's own normal
    kShadeBlend = 1u << 16,         // Material::blend: the alpha is written for blending (opaque: 1)
    kShadePunctual = 1u << 17,      // the renderer has punctual lights (Renderer::setPunctualLights)
    // The occlusion map is the metallic-roughness texture (glTF's common "ORM" packing: occlusion in R), read with
    // the same UVs: its sample is taken once (with kShadePbrMr and kShadePbrOcclusion).
    kShadePbrOrm = 1u << 18,
    // Per-feature colours (Renderer::setFeatureStyle): the vertex's feature id reads the feature's colour from a
    // table, which multiplies the base colour; alpha 0 hides the feature. Both families.
    kShadeFeature = 1u << 19,
    // Points (Mesh::primitive()): the vertex stage sizes them (gl_PointSize, Renderer::pointShading()). Both families.
    kShadePoint = 1u << 20,
    kShadeRound = 1u << 21,  // round points: the fragment stage drops what lies outside the disc (with kShadePoint)
    // Lines wider than the context draws (a forward-compatible context draws none wider than 1 pixel): a geometry
    // stage turns each segment into a quad of the width (variantGeometrySource). Both families.
    kShadeWideLine = 1u << 22,
    // A triangle mesh's outline (Mesh::outline()), drawn as lines over its faces: black, as opaque as the base colour,
    // unlit. Classic family only.
    kShadeOutline = 1u << 23,
    // Skinned (a Pose with joints, DrawList::poses): the vertex stage moves each vertex by the weighted sum of its
    // joints' matrices, 4 or 8 influences a vertex (Mesh::influences()). Both families, and points, lines and outlines.
    kShadeSkin4 = 1u << 24,
    kShadeSkin8 = 1u << 25,
};
// Punctual lights a physical draw receives at most.
constexpr int kMaxPunctualLights = 8;
// The features that change a variant's code: those that have no effect alone are dropped (baked light without
// vertex colours, light terms of an unlit draw, a highlight under the headlight).
uint32_t canonicalFeatures(uint32_t features);
// A variant's vertex or fragment source for these features.
std::string variantSource(bool vertex, uint32_t features);
// A variant's geometry source (kShadeWideLine), empty for the variants that have no geometry stage.
std::string variantGeometrySource(uint32_t features);

// Per vertex, from a mesh's buffer (what the Mesh holds).
constexpr unsigned kPositionLocation = 0, kNormalLocation = 1, kUvLocation = 2, kColorLocation = 3;
// Read by physical materials' programs only, after the item attributes (locations 4 to 8).
constexpr unsigned kTangentLocation = 9, kUv1Location = 10;
// A mesh's feature ids of its first feature ID set, as floats (exact below 2^24), for kShadeFeature.
constexpr unsigned kFeatureIdLocation = 11;
// A skinned mesh's joint indices (unsigned, uvec4) and weights (vec4): its first four influences, then its next four.
constexpr unsigned kJointsLocation = 12, kJoints1Location = 13, kWeightsLocation = 14, kWeights1Location = 15;
// The joints' matrices a skinned draw reads: a uniform block (std140) of kMaxJoints 4x3 matrices, each as mat3x4 (its
// three rows, 48 bytes), bound at kJointBinding. GL 3.3 promises blocks of 16 KB: 256 joints take 12 KB.
constexpr int kMaxJoints = 256;
constexpr unsigned kJointBinding = 0;
constexpr size_t kJointBlockBytes = size_t(kMaxJoints) * 48;
// The texture units of a physical material's textures (the classic programs read unit 0 only).
constexpr int kBaseColorUnit = 0, kMetallicRoughnessUnit = 1, kNormalUnit = 2, kOcclusionUnit = 3, kEmissiveUnit = 4;
// The per-feature colour table's unit (kShadeFeature): RGBA8, feature id i at texel (i % width, i / width).
constexpr int kFeatureUnit = 5;
// The variants' vertex stage, one source for both families (ShadersVertex.cpp), after the #defines variantSource()
// writes; physical: as the physical fragment stage reads it.
std::string variantVertexSource(bool physical);
// The wide lines' geometry stage (ShadersVertex.cpp), after the #defines variantSource() writes and EYE (whether the
// fragment stage reads vFromEye).
extern const char* const kWideLineGeometryStage;
// A physical variant's fragment source (ShadersPbr.cpp), after the #defines variantSource() writes.
extern const char* const kPbrFragmentShader;

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
