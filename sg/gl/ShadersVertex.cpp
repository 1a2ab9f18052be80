// The variants' vertex stage: one source that the classic and the physical variants both compile, after the
// #defines variantSource() writes. The two families differ in two outputs only, substituted per family ($EYE_IF,
// $UV0_IF, $UV0_OUT): the eye offset (a classic draw reads it for the sun's light alone, a physical one always)
// and the first UV set's (the classic fragment stage reads it as vUv, the physical one as vUv0). The rest reads
// macros that the classic features leave at 0 (FLAT, PBR_NORMAL, UV1), so one text serves both. The wide lines'
// geometry stage (kShadeWideLine), which runs after it, is here too.
#include "sg/gl/internal/Shaders.h"

#include <cstring>
#include <string>

namespace sg {

namespace {

const char* const kVertexStage = R"(
layout(location = 0) in vec3 aPosition;
layout(location = 4) in mat4 aModel;
layout(location = 8) in vec4 aBaseColor;
uniform mat4 uViewProj;
flat out vec4 vBaseColor;
#if $EYE_IF
out vec3 vFromEye;  // world offset from the eye: the models' matrices carry the eye's translation
#endif
#if LIT && !FLAT
layout(location = 1) in vec3 aNormal;
out vec3 vNormal;
#endif
#if PBR_NORMAL
layout(location = 9) in vec4 aTangent;
out vec4 vTangent;
#endif
#if $UV0_IF
layout(location = 2) in vec2 aUv;
out vec2 $UV0_OUT;
#endif
#if UV1
layout(location = 10) in vec2 aUv1;
out vec2 vUv1;
#endif
#if COLOR
layout(location = 3) in vec4 aColor;
out vec4 vColor;
#endif
#if FEATURE
layout(location = 11) in float aFeatureId;
uniform sampler2D uFeatureColors;
#endif
#if POINT
// Renderer::pointShading(): the fixed size and the largest attenuated one; uPointScale the mesh's point spacing (x the
// spacing scale) in pixels at distance 1, 0 for the fixed size.
uniform float uPointSize, uMaxPointSize, uPointScale;
#endif
#if SKIN4 || SKIN8
layout(location = 12) in uvec4 aJoints;
layout(location = 14) in vec4 aWeights;
#if SKIN8
layout(location = 13) in uvec4 aJoints1;
layout(location = 15) in vec4 aWeights1;
#endif
// The pose's joint matrices less its anchor (sg/core/Pose.h), each as its three rows: p goes to vec4(p, 1) * joint.
layout(std140) uniform Joints {
    mat3x4 uJoints[$MAX_JOINTS];
};
// The weighted sum of four joints' matrices. An index past the block (its weight 0: the renderer checks the others)
// reads the last joint rather than past the array.
mat3x4 blend(uvec4 j, vec4 w) {
    j = min(j, uvec4($MAX_JOINTS - 1));
    return w.x * uJoints[j.x] + w.y * uJoints[j.y] + w.z * uJoints[j.z] + w.w * uJoints[j.w];
}
#endif
void main() {
#if SKIN4 || SKIN8
    // Skinned (glTF): the vertex by the weighted sum of its joints' matrices, then the item's matrix (the translation
    // from the eye to the anchor); normals and tangents by both matrices' 3x3 parts, as for an unskinned item.
    mat3x4 skin = blend(aJoints, aWeights);
#if SKIN8
    skin += blend(aJoints1, aWeights1);
#endif
    vec4 world = aModel * vec4(vec4(aPosition, 1.0) * skin, 1.0);
#else
    vec4 world = aModel * vec4(aPosition, 1.0);
#endif
    gl_Position = uViewProj * world;
#if POINT
    // w is the distance along the view (perspective) or 1 (orthographic, where the scale holds at any depth).
    gl_PointSize =
        uPointScale > 0.0 ? max(min(uPointScale / gl_Position.w, uMaxPointSize), uPointSize) : uPointSize;
#endif
#if $EYE_IF
    vFromEye = world.xyz;
#endif
#if ((LIT && !FLAT) || PBR_NORMAL) && (SKIN4 || SKIN8)
    mat3 m = mat3(aModel) * transpose(mat3(skin));  // mat3(skin): the 3x3 part's transpose (skin holds rows)
#elif (LIT && !FLAT) || PBR_NORMAL
    mat3 m = mat3(aModel);
#endif
#if LIT && !FLAT
    // The cofactor matrix (det x inverse-transpose): right under non-uniform scale; its sign, which a mirror turns,
    // each fragment stage settles (the classic one toward the eye, the physical one by the facing).
    vNormal = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1])) * aNormal;
#endif
#if PBR_NORMAL
    vTangent = vec4(m * aTangent.xyz, aTangent.w);
#endif
#if $UV0_IF
    $UV0_OUT = aUv;
#endif
#if UV1
    vUv1 = aUv1;
#endif
#if COLOR
    vColor = aColor;
#endif
#if OUTLINE
    vBaseColor = vec4(0.0, 0.0, 0.0, aBaseColor.a);  // an outline is black, as opaque as its faces
#else
    vBaseColor = aBaseColor;
#endif
#if FEATURE
    // The feature's colour multiplies the base colour (3D Tiles styles' HIGHLIGHT blending); alpha 0 hides the
    // feature: its vertices go beyond the far plane, where clipping drops its triangles (a feature's triangles
    // have all three corners in it). An id outside the table (the null feature) keeps the base colour.
    ivec2 size = textureSize(uFeatureColors, 0);
    int id = int(aFeatureId);
    if (id >= 0 && id < size.x * size.y) {
        vec4 fc = texelFetch(uFeatureColors, ivec2(id % size.x, id / size.x), 0);
        vBaseColor.rgb *= fc.rgb;
        if (fc.a == 0.0) gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    }
#endif
}
)";

}  // namespace

// Lines carry no normals or UVs (Mesh::setLines): the base colour, the vertex colours and the eye offset are all a
// line's fragment stage reads.
const char* const kWideLineGeometryStage = R"(
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
uniform vec2 uViewportSize;  // pixels
uniform float uLineWidth;    // pixels
flat in vec4 vBaseColor[];
flat out vec4 gBaseColor;
#if COLOR
in vec4 vColor[];
out vec4 gColor;
#endif
#if EYE
in vec3 vFromEye[];
out vec3 gFromEye;
#endif
// A corner: the clip-space point p moved by `across` in normalized device coordinates (times w: before the divide),
// with the attributes at t along the segment.
void corner(vec4 p, vec2 across, float t) {
    gl_Position = vec4(p.xy + across * p.w, p.zw);
    gBaseColor = vBaseColor[0];
#if COLOR
    gColor = mix(vColor[0], vColor[1], t);
#endif
#if EYE
    gFromEye = mix(vFromEye[0], vFromEye[1], t);
#endif
    EmitVertex();
}
void main() {
    // The part of the segment in front of the eye (w above a small bound): only there can w divide; the near plane,
    // farther out, clips the quad's rest.
    const float minW = 1e-5;
    vec4 p0 = gl_in[0].gl_Position, p1 = gl_in[1].gl_Position;
    if (p0.w < minW && p1.w < minW) return;
    float t0 = p0.w < minW ? (minW - p0.w) / (p1.w - p0.w) : 0.0;
    float t1 = p1.w < minW ? (minW - p0.w) / (p1.w - p0.w) : 1.0;
    vec4 a = mix(p0, p1, t0), b = mix(p0, p1, t1);
    vec2 d = (b.xy / b.w - a.xy / a.w) * uViewportSize;  // along the segment on screen, in proportion to pixels
    float len = length(d);
    vec2 dir = len > 0.0 ? d / len : vec2(1.0, 0.0);
    // Half the width either side: w/2 pixels are w/2 x 2/size in normalized device coordinates.
    vec2 across = vec2(-dir.y, dir.x) * uLineWidth / uViewportSize;
    corner(a, -across, t0);
    corner(a, across, t0);
    corner(b, -across, t1);
    corner(b, across, t1);
    EndPrimitive();
}
)";

namespace {

// What differs between the families: the condition of the eye offset, that of the first UV set, and its name.
struct Family {
    const char *eyeIf, *uv0If, *uv0Out;
};
constexpr Family kClassic{"LIT && SUN", "TEXTURE", "vUv"}, kPhysical{"1", "UV0", "vUv0"};

// Replaces every `from` in s by `to`.
void substitute(std::string& s, const char* from, const char* to) {
    const size_t n = std::strlen(from), m = std::strlen(to);
    for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + m)) s.replace(at, n, to);
}

}  // namespace

std::string variantVertexSource(bool physical) {
    const Family& f = physical ? kPhysical : kClassic;
    std::string s = kVertexStage;
    substitute(s, "$EYE_IF", f.eyeIf);
    substitute(s, "$UV0_IF", f.uv0If);
    substitute(s, "$UV0_OUT", f.uv0Out);
    substitute(s, "$MAX_JOINTS", std::to_string(kMaxJoints).c_str());
    return s;
}

}  // namespace sg
