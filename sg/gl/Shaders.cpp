#include "sg/gl/internal/Shaders.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <utility>

namespace sg {

const char* const kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(location = 3) in vec4 aColor;
layout(location = 4) in mat4 aModel;  // per instance: locations 4 to 7
// The material's base colour, per instance: the value that differs between most materials. As a uniform it
// would change between most draws, and llvmpipe stores its whole rasterizer state again for every draw whose
// uniforms differ from the one before (docs/architecture.md, "Draw list and draw").
layout(location = 8) in vec4 aBaseColor;
uniform mat4 uViewProj;
out vec3 vNormal;
out vec3 vFromEye;  // world offset from the eye: the models' matrices carry the eye's translation
out vec2 vUv;
out vec4 vColor;
flat out vec4 vBaseColor;
void main() {
    vec4 world = aModel * vec4(aPosition, 1.0);
    vFromEye = world.xyz;
    gl_Position = uViewProj * world;
    // The cofactor matrix is det * inverse-transpose: right under non-uniform scale, and its sign does
    // not matter with two-sided lighting.
    mat3 m = mat3(aModel);
    vNormal = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1])) * aNormal;
    vUv = aUv;
    vColor = aColor;
    vBaseColor = aBaseColor;
}
)";

const char* const kFragmentShader = R"(#version 330 core
in vec3 vNormal;
in vec3 vFromEye;
in vec2 vUv;
in vec4 vColor;
flat in vec4 vBaseColor;
uniform vec3 uLightDir;  // unit, toward the light (the headlight: the view direction)
uniform bool uHeadlight;
uniform vec3 uAmbient, uLightColor;  // DirectionalLight, when not the headlight
uniform bool uUseTexture;
uniform bool uUseColor;
uniform bool uBakedLight;  // Material::bakedLight: vertex alpha is sun visibility, not opacity
uniform bool uLit;
uniform float uSpecular, uShininess;
uniform sampler2D uTexture;
uniform float uAlphaCutoff;  // Material::alphaCutoff
uniform float uFade;  // DrawList::fades: 1 opaque; f > 0 keeps pattern < f; f < 0 keeps pattern >= 1 + f
out vec4 fragColor;
void main() {
    if (uFade < 1.0) {
        // Interleaved gradient noise (Jimenez 2014): a pattern value per pixel, evenly spread, no visible grid.
        float n = fract(52.9829189 * fract(dot(floor(gl_FragCoord.xy), vec2(0.06711056, 0.00583715))));
        if (uFade > 0.0 ? n >= uFade : n < 1.0 + uFade) discard;
    }
    vec4 c = vBaseColor;
    if (uUseTexture) c *= texture(uTexture, vUv);
    float sun = 1.0;
    if (uUseColor) {
        if (uBakedLight) {
            c.rgb *= vColor.rgb;
            sun = vColor.a;
        } else {
            c *= vColor;
        }
    }
    if (c.a < uAlphaCutoff) discard;
    if (uLit) {
        float len = length(vNormal);
        if (uHeadlight) {
            float d = len > 0.0 ? abs(dot(vNormal / len, uLightDir)) : 1.0;
            c.rgb *= 0.35 + 0.65 * d * sun;
        } else {
            vec3 v = -normalize(vFromEye);
            vec3 n = len > 0.0 ? vNormal / len : v;
            if (dot(n, v) < 0.0) n = -n;  // the side the eye sees: normals' sign varies with winding and mirroring
            float nl = max(dot(n, uLightDir), 0.0);
            vec3 direct = uLightColor * (nl * sun);
            vec3 rgb = c.rgb * (uAmbient + direct);
            if (uSpecular > 0.0 && nl > 0.0)
                rgb += uLightColor * (sun * uSpecular * pow(max(dot(n, normalize(uLightDir + v)), 0.0), uShininess));
            c.rgb = rgb;
        }
    }
    fragColor = c;
}
)";

// The variants: the same arithmetic as the one program above, with each feature a preprocessor constant, so
// that a variant declares only the attributes, outputs and uniforms its draws use and its fragment stage has no
// branch on a uniform (llvmpipe runs the fragment shader per pixel in software: every interpolated output and
// every branch is paid for at each pixel). Their vertex stage is the physical variants' too (ShadersVertex.cpp).
const char* const kVariantFragmentShader = R"(
flat in vec4 vBaseColor;
#if LIT
in vec3 vNormal;
uniform vec3 uLightDir;
#if SUN
in vec3 vFromEye;
uniform vec3 uAmbient, uLightColor;
#if SPECULAR
uniform float uSpecular, uShininess;
#endif
#endif
#endif
#if TEXTURE
in vec2 vUv;
uniform sampler2D uTexture;
#endif
#if COLOR
in vec4 vColor;
#endif
#if ALPHA_CUT
uniform float uAlphaCutoff;
#endif
#if FADE
uniform float uFade;
#endif
out vec4 fragColor;
void main() {
#if ROUND
    // The disc inscribed in the point's square (gl_PointCoord runs 0 to 1 across it).
    if (dot(gl_PointCoord - 0.5, gl_PointCoord - 0.5) > 0.25) discard;
#endif
#if FADE
    {
        float n = fract(52.9829189 * fract(dot(floor(gl_FragCoord.xy), vec2(0.06711056, 0.00583715))));
        if (uFade > 0.0 ? n >= uFade : n < 1.0 + uFade) discard;
    }
#endif
    vec4 c = vBaseColor;
#if TEXTURE
    c *= texture(uTexture, vUv);
#endif
    float sun = 1.0;
#if COLOR && BAKED
    c.rgb *= vColor.rgb;
    sun = vColor.a;
#elif COLOR
    c *= vColor;
#endif
#if ALPHA_CUT
    if (c.a < uAlphaCutoff) discard;
#endif
#if LIT && !SUN
    float len = length(vNormal);
    float d = len > 0.0 ? abs(dot(vNormal / len, uLightDir)) : 1.0;
    c.rgb *= 0.35 + 0.65 * d * sun;
#elif LIT
    float len = length(vNormal);
    vec3 v = -normalize(vFromEye);
    vec3 n = len > 0.0 ? vNormal / len : v;
    if (dot(n, v) < 0.0) n = -n;
    float nl = max(dot(n, uLightDir), 0.0);
    vec3 direct = uLightColor * (nl * sun);
    vec3 rgb = c.rgb * (uAmbient + direct);
#if SPECULAR
    if (nl > 0.0) rgb += uLightColor * (sun * uSpecular * pow(max(dot(n, normalize(uLightDir + v)), 0.0), uShininess));
#endif
    c.rgb = rgb;
#endif
    fragColor = c;
}
)";

uint32_t canonicalFeatures(uint32_t f) {
    if (f & kShadePoint)
        f &= ~(kShadeWideLine | kShadeOutline);
    else
        f &= ~kShadeRound;                   // a disc is a point's
    if (f & kShadeSkin8) f &= ~kShadeSkin4;  // eight influences read the first four too
    // Black, unlit; moved as its faces are.
    if (f & kShadeOutline) f &= kShadeOutline | kShadeWideLine | kShadeFade | kShadeFeature | kShadeSkin4 | kShadeSkin8;
    constexpr uint32_t pbrOnly = kShadePbrMr | kShadePbrNormal | kShadePbrOcclusion | kShadePbrEmissive | kShadeUv0 |
                                 kShadeUv1 | kShadeFlat | kShadeBlend | kShadePunctual | kShadePbrOrm;
    if (f & kShadePbr) {
        f &= ~(kShadeBaked | kShadeSpecular);  // the classic terms
        // Unlit: the base colour alone.
        if (!(f & kShadeLit))
            f &= ~(kShadeSun | kShadePbrMr | kShadePbrNormal | kShadePbrOcclusion | kShadePbrEmissive | kShadeFlat |
                   kShadePunctual | kShadePbrOrm);
        if (f & kShadeFlat) f &= ~kShadePbrNormal;  // a normal map needs the mesh's normals and tangents
        if (!(f & kShadePbrMr) || !(f & kShadePbrOcclusion)) f &= ~kShadePbrOrm;
        return f;
    }
    f &= ~pbrOnly;
    if (!(f & kShadeColor)) f &= ~kShadeBaked;                 // baked light is read from the vertex colours
    if (!(f & kShadeLit)) f &= ~(kShadeSun | kShadeSpecular);  // light, sun and highlight only for lit draws
    if (!(f & kShadeSun)) f &= ~kShadeSpecular;                // the headlight has no highlight
    return f;
}

namespace {

// The #version line and a #define per feature, 1 or 0: what every stage of a variant starts with.
std::string variantDefines(uint32_t f) {
    std::string s = "#version 330 core\n";
    const std::pair<uint32_t, const char*> names[] = {{kShadeTexture, "TEXTURE"},
                                                      {kShadeColor, "COLOR"},
                                                      {kShadeBaked, "BAKED"},
                                                      {kShadeLit, "LIT"},
                                                      {kShadeSun, "SUN"},
                                                      {kShadeSpecular, "SPECULAR"},
                                                      {kShadeAlphaCut, "ALPHA_CUT"},
                                                      {kShadeFade, "FADE"},
                                                      {kShadePbrMr, "PBR_MR"},
                                                      {kShadePbrNormal, "PBR_NORMAL"},
                                                      {kShadePbrOcclusion, "PBR_OCCLUSION"},
                                                      {kShadePbrEmissive, "PBR_EMISSIVE"},
                                                      {kShadeUv0, "UV0"},
                                                      {kShadeUv1, "UV1"},
                                                      {kShadeFlat, "FLAT"},
                                                      {kShadeBlend, "BLEND"},
                                                      {kShadePunctual, "PUNCTUAL"},
                                                      {kShadePbrOrm, "PBR_ORM"},
                                                      {kShadeFeature, "FEATURE"},
                                                      {kShadePoint, "POINT"},
                                                      {kShadeRound, "ROUND"},
                                                      {kShadeWideLine, "WIDE_LINE"},
                                                      {kShadeOutline, "OUTLINE"},
                                                      {kShadeSkin4, "SKIN4"},
                                                      {kShadeSkin8, "SKIN8"}};
    for (const auto& [bit, name] : names) s += std::string("#define ") + name + ((f & bit) ? " 1\n" : " 0\n");
    return s;
}

// The fragment stage behind a geometry stage reads what that stage writes: the vertex stage's outputs renamed (a
// geometry stage cannot give an output the name of its input).
const char* const kWideLineRenames =
    "#define vBaseColor gBaseColor\n#define vColor gColor\n#define vFromEye gFromEye\n";

}  // namespace

std::string variantSource(bool vertex, uint32_t features) {
    const uint32_t f = canonicalFeatures(features);
    const std::string s = variantDefines(f);
    if (vertex) return s + variantVertexSource((f & kShadePbr) != 0);
    return s + ((f & kShadeWideLine) ? kWideLineRenames : "") +
           ((f & kShadePbr) ? kPbrFragmentShader : kVariantFragmentShader);
}

std::string variantGeometrySource(uint32_t features) {
    const uint32_t f = canonicalFeatures(features);
    if (!(f & kShadeWideLine)) return {};
    // vFromEye: the physical fragment stage always reads it, the classic one for the sun's light alone.
    const bool eye = (f & kShadePbr) || ((f & kShadeLit) && (f & kShadeSun));
    return variantDefines(f) + (eye ? "#define EYE 1\n" : "#define EYE 0\n") + kWideLineGeometryStage;
}

namespace {
constexpr GLuint kItemLocation = 4;
constexpr GLuint kItemVec4s = sizeof(ItemAttributes) / sizeof(vec4);  // the matrix's 4 columns, the base colour
static_assert(sizeof(ItemAttributes) == 5 * sizeof(vec4), "the vertex shader reads a mat4 and a vec4 per item");
}  // namespace

void enableItemAttributes() {
    for (GLuint c = 0; c < kItemVec4s; ++c) {
        glEnableVertexAttribArray(kItemLocation + c);
        glVertexAttribDivisor(kItemLocation + c, 1);
    }
}

void pointItemAttributes(size_t first) {
    const size_t offset = first * sizeof(ItemAttributes);
    for (GLuint c = 0; c < kItemVec4s; ++c)
        glVertexAttribPointer(kItemLocation + c, 4, GL_FLOAT, GL_FALSE, sizeof(ItemAttributes),
                              reinterpret_cast<const void*>(offset + c * sizeof(vec4)));
}

}  // namespace sg
