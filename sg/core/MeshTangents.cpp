// Tangent generation for normal maps when a file gives none (glTF asks for MikkTSpace's tangents then).
#include "sg/core/Mesh.h"

#include <cmath>
#include <stdexcept>

namespace sg {

namespace {

// Any unit vector orthogonal to n (n unit or zero).
vec3 orthogonal(const vec3& n) {
    const vec3 a = std::abs(n.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    const vec3 t = glm::cross(n, a);
    const float len = glm::length(t);
    return len > 0.0f ? t / len : vec3(1.0f, 0.0f, 0.0f);
}

float cornerAngle(const vec3& at, const vec3& a, const vec3& b) {
    const vec3 u = a - at, v = b - at;
    const float lu = glm::length(u), lv = glm::length(v);
    if (!(lu > 0.0f && lv > 0.0f)) return 0.0f;
    return std::acos(glm::clamp(glm::dot(u, v) / (lu * lv), -1.0f, 1.0f));
}

}  // namespace

std::vector<vec4> generateTangents(const Mesh& mesh, int texCoord) {
    const std::vector<vec3>& p = mesh.positions();
    const std::vector<vec3>& n = mesh.normals();
    const std::vector<vec2>& uv = texCoord == 1 ? mesh.uvs1() : mesh.uvs();
    if (texCoord != 0 && texCoord != 1)
        throw std::invalid_argument("generateTangents(): texCoord " + std::to_string(texCoord) + " is not 0 or 1");
    if (n.size() != p.size() || uv.size() != p.size())
        throw std::invalid_argument("generateTangents(): the mesh needs normals and UV set " +
                                    std::to_string(texCoord));
    std::vector<vec3> t(p.size(), vec3(0.0f)), b(p.size(), vec3(0.0f));
    for (uint32_t k = 0; k < 3 * mesh.triangleCount(); k += 3) {
        const uint32_t i[3] = {mesh.index(k), mesh.index(k + 1), mesh.index(k + 2)};
        const vec3 e1 = p[i[1]] - p[i[0]], e2 = p[i[2]] - p[i[0]];
        const vec2 d1 = uv[i[1]] - uv[i[0]], d2 = uv[i[2]] - uv[i[0]];
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) continue;
        // Unnormalized: MikkTSpace normalizes each triangle's vectors before weighting by the corner angle.
        const vec3 ft = (e1 * d2.y - e2 * d1.y) / det, fb = (e2 * d1.x - e1 * d2.x) / det;
        const float lt = glm::length(ft), lb = glm::length(fb);
        if (!(lt > 0.0f && lb > 0.0f) || !std::isfinite(lt) || !std::isfinite(lb)) continue;
        for (int c = 0; c < 3; ++c) {
            const float w = cornerAngle(p[i[c]], p[i[(c + 1) % 3]], p[i[(c + 2) % 3]]);
            t[i[c]] += w * ft / lt;
            b[i[c]] += w * fb / lb;
        }
    }
    std::vector<vec4> out(p.size());
    for (size_t v = 0; v < p.size(); ++v) {
        const float ln = glm::length(n[v]);
        const vec3 nn = ln > 0.0f ? n[v] / ln : vec3(0.0f, 0.0f, 1.0f);
        vec3 tt = t[v] - nn * glm::dot(nn, t[v]);  // Gram-Schmidt against the normal
        const float lt = glm::length(tt);
        tt = lt > 1e-12f && std::isfinite(lt) ? tt / lt : orthogonal(nn);
        const float w = glm::dot(glm::cross(nn, tt), b[v]) < 0.0f ? -1.0f : 1.0f;
        out[v] = vec4(tt, w);
    }
    return out;
}

}  // namespace sg
