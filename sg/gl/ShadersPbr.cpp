// The metallic-roughness program's fragment source (its vertex stage is the classic variants', ShadersVertex.cpp):
// glTF 2.0's BRDF as its Appendix B writes it (Lambert diffuse, GGX distribution, the separable Smith visibility,
// Schlick's Fresnel), in linear space, written out as sRGB. The features are preprocessor constants, as for the classic
// variants (Shaders.cpp): a draw pays only for what its material uses.
#include "sg/gl/internal/Shaders.h"

namespace sg {

const char* const kPbrFragmentShader = R"(
const float PI = 3.14159265358979;
flat in vec4 vBaseColor;
in vec3 vFromEye;
#if LIT && !FLAT
in vec3 vNormal;
#endif
#if PBR_NORMAL
in vec4 vTangent;
uniform sampler2D uNormalTex;
uniform float uNormalScale;
uniform mat3 uNormalXf;
uniform int uNormalSet;
#endif
#if UV0
in vec2 vUv0;
#endif
#if UV1
in vec2 vUv1;
#endif
#if COLOR
in vec4 vColor;
#endif
#if TEXTURE
uniform sampler2D uTexture;
uniform mat3 uBaseXf;
uniform int uBaseSet;
#endif
#if LIT
uniform vec3 uLightDir;    // unit, toward the sun (SUN; the headlight shines from the eye)
uniform vec3 uLightE;      // its irradiance at normal incidence
uniform vec3 uSky, uGround, uUp;
uniform float uMetallic, uRoughness;
uniform vec3 uEmissive;
#if PBR_MR
uniform sampler2D uMrTex;
uniform mat3 uMrXf;
uniform int uMrSet;
#endif
#if PBR_OCCLUSION
uniform sampler2D uOcclusionTex;
uniform float uOcclusionStrength;
uniform mat3 uOcclusionXf;
uniform int uOcclusionSet;
#endif
#if PBR_EMISSIVE
uniform sampler2D uEmissiveTex;
uniform mat3 uEmissiveXf;
uniform int uEmissiveSet;
#endif
#if PUNCTUAL
uniform int uLightCount;
uniform vec4 uPunctualPos[8];   // eye-relative position; w: 0 directional, 1 point, 2 spot
uniform vec4 uPunctualDir[8];   // xyz the way the light travels; w the range (0: unlimited)
uniform vec3 uPunctualE[8];     // colour x intensity
uniform vec2 uPunctualCone[8];  // spot: scale and offset of the cosine (KHR_lights_punctual)
#endif
#endif
#if ALPHA_CUT
uniform float uAlphaCutoff;
#endif
#if FADE
uniform float uFade;
#endif
out vec4 fragColor;

vec2 uvOf(int set, mat3 xf) {
#if UV0 && UV1
    vec2 uv = set == 1 ? vUv1 : vUv0;
#elif UV1
    vec2 uv = vUv1;
#elif UV0
    vec2 uv = vUv0;
#else
    vec2 uv = vec2(0.0);
#endif
    return (xf * vec3(uv, 1.0)).xy;
}

vec3 toSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

#if LIT
// One light's share: (diffuse + specular BRDF) x irradiance x n.l (glTF 2.0, Appendix B).
vec3 shade(vec3 n, vec3 v, vec3 l, vec3 e, vec3 cDiff, vec3 f0, float a2) {
    float nl = dot(n, l);
    if (nl <= 0.0) return vec3(0.0);
    vec3 h = normalize(l + v);
    float nv = abs(dot(n, v)), nh = max(dot(n, h), 0.0), vh = abs(dot(v, h));
    vec3 f = f0 + (1.0 - f0) * pow(max(1.0 - vh, 0.0), 5.0);  // pow of a negative is undefined
    float dd = nh * nh * (a2 - 1.0) + 1.0;
    float d = a2 / (PI * dd * dd);
    float vis = 1.0 / ((nl + sqrt(a2 + (1.0 - a2) * nl * nl)) * (nv + sqrt(a2 + (1.0 - a2) * nv * nv)));
    return ((1.0 - f) * cDiff / PI + f * d * vis) * e * nl;
}
#endif

void main() {
#if ROUND
    if (dot(gl_PointCoord - 0.5, gl_PointCoord - 0.5) > 0.25) discard;  // the disc inscribed in the point's square
#endif
#if FADE
    {
        float n = fract(52.9829189 * fract(dot(floor(gl_FragCoord.xy), vec2(0.06711056, 0.00583715))));
        if (uFade > 0.0 ? n >= uFade : n < 1.0 + uFade) discard;
    }
#endif
    vec4 c = vBaseColor;
#if TEXTURE
    c *= texture(uTexture, uvOf(uBaseSet, uBaseXf));
#endif
#if COLOR
    c *= vColor;
#endif
#if ALPHA_CUT
    if (c.a < uAlphaCutoff) discard;
#endif
#if BLEND
    float alpha = c.a;
#else
    float alpha = 1.0;
#endif
#if !LIT
    fragColor = vec4(toSrgb(c.rgb), alpha);
#else
    vec3 v = -normalize(vFromEye);
#if FLAT
    vec3 n = normalize(cross(dFdx(vFromEye), dFdy(vFromEye)));
    if (dot(n, v) < 0.0) n = -n;
#else
    float len = length(vNormal);
    vec3 n = len > 0.0 ? vNormal / len : v;
    if (!gl_FrontFacing) n = -n;  // the back of a double-sided surface: its normal reversed (glTF)
#endif
#if PBR_NORMAL
    {
        vec3 t = vTangent.xyz - n * dot(n, vTangent.xyz);
        float lt = length(t);
        if (lt > 0.0) {
            t /= lt;
            vec3 b = cross(n, t) * (vTangent.w < 0.0 ? -1.0 : 1.0);
            if (!gl_FrontFacing) b = -b;
            vec3 tn = texture(uNormalTex, uvOf(uNormalSet, uNormalXf)).xyz * 2.0 - 1.0;
            tn.xy *= uNormalScale;
            vec3 m = t * tn.x + b * tn.y + n * tn.z;
            float lm = length(m);
            if (lm > 0.0) n = m / lm;
        }
    }
#endif
    float metallic = uMetallic, roughness = uRoughness;
#if PBR_MR
    vec4 mr = texture(uMrTex, uvOf(uMrSet, uMrXf));
    roughness *= mr.g;
    metallic *= mr.b;
#endif
    metallic = clamp(metallic, 0.0, 1.0);
    roughness = clamp(roughness, 0.0, 1.0);
    vec3 cDiff = mix(c.rgb, vec3(0.0), metallic);
    vec3 f0 = mix(vec3(0.04), c.rgb, metallic);
    float a = roughness * roughness;
    float a2 = max(a * a, 1e-7);  // a mirror-smooth surface: a highlight of one pixel, not a division by 0
#if SUN
    vec3 rgb = shade(n, v, uLightDir, uLightE, cDiff, f0, a2);
#else
    vec3 rgb = shade(n, v, v, uLightE, cDiff, f0, a2);  // the headlight: a light at the eye
#endif
#if PUNCTUAL
    for (int i = 0; i < uLightCount; ++i) {
        vec3 l = -uPunctualDir[i].xyz;
        vec3 e = uPunctualE[i];
        if (uPunctualPos[i].w > 0.5) {  // point or spot
            vec3 toLight = uPunctualPos[i].xyz - vFromEye;
            float d2 = max(dot(toLight, toLight), 1e-8);
            l = toLight * inversesqrt(d2);
            float range = uPunctualDir[i].w;
            float fall = range > 0.0 ? clamp(1.0 - pow(d2 / (range * range), 2.0), 0.0, 1.0) : 1.0;
            e *= fall / d2;
            if (uPunctualPos[i].w > 1.5) {
                float cone = clamp(dot(uPunctualDir[i].xyz, -l) * uPunctualCone[i].x + uPunctualCone[i].y, 0.0, 1.0);
                e *= cone * cone;
            }
        }
        rgb += shade(n, v, l, e, cDiff, f0, a2);
    }
#endif
    // The environment: a sky and ground hemisphere, diffuse by the normal, specular by the reflected ray with the
    // analytic fit of the split-sum's scale and bias (Karis 2014, "Physically Based Shading on Mobile").
    float nv = abs(dot(n, v));
    vec3 r = reflect(-v, n);
    vec3 envDiffuse = mix(uGround, uSky, 0.5 + 0.5 * dot(n, uUp));
    vec3 envSpecular = mix(uGround, uSky, 0.5 + 0.5 * dot(r, uUp));
    const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022), c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 k = roughness * c0 + c1;
    float a004 = min(k.x * k.x, exp2(-9.28 * nv)) * k.x + k.y;
    vec2 ab = vec2(-1.04, 1.04) * a004 + k.zw;
    vec3 ambient = cDiff * envDiffuse + envSpecular * (f0 * ab.x + ab.y);
#if PBR_OCCLUSION
#if PBR_ORM
    float ao = mr.r;  // the metallic-roughness texture's sample, already taken
#else
    float ao = texture(uOcclusionTex, uvOf(uOcclusionSet, uOcclusionXf)).r;
#endif
    ambient *= 1.0 + uOcclusionStrength * (ao - 1.0);
#endif
    rgb += ambient;
    vec3 emissive = uEmissive;
#if PBR_EMISSIVE
    emissive *= texture(uEmissiveTex, uvOf(uEmissiveSet, uEmissiveXf)).rgb;
#endif
    rgb += emissive;
    fragColor = vec4(toSrgb(rgb), alpha);
#endif
}
)";

}  // namespace sg
