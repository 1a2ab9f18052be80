#include "testbed/Materials.h"

#include "nodes/Geometry.h"
#include "nodes/Transform.h"

#include <algorithm>
#include <cmath>

namespace scenes {

using namespace sg;

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

ref_ptr<Mesh> makeSphereMesh(float r, int slices, int stacks) {
    std::vector<vec3> p, n;
    std::vector<vec2> uv;
    std::vector<uint32_t> idx;
    for (int j = 0; j <= stacks; ++j)
        for (int i = 0; i <= slices; ++i) {
            const double th = kPi * j / stacks, ph = 2.0 * kPi * i / slices;
            const vec3 d(float(std::sin(th) * std::cos(ph)), float(std::cos(th)), float(-std::sin(th) * std::sin(ph)));
            n.push_back(d);
            p.push_back(d * r);
            uv.push_back(vec2(float(i) / float(slices), float(j) / float(stacks)));
        }
    const uint32_t row = uint32_t(slices + 1);
    for (uint32_t j = 0; j < uint32_t(stacks); ++j)
        for (uint32_t i = 0; i < uint32_t(slices); ++i) {
            const uint32_t a = j * row + i, b = a + row;
            idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
    auto m = make<Mesh>();
    m->set(std::move(p), std::move(n), std::move(idx), std::move(uv));
    m->setSurface(generateTangents(*m, 0), {});
    return m;
}

namespace {

ref_ptr<Mesh> quad(const vec3& a, const vec3& b, const vec3& c, const vec3& d, const vec3& normal) {
    auto m = make<Mesh>();
    m->set({a, b, c, d}, std::vector<vec3>(4, normal), {0, 1, 2, 0, 2, 3}, {{0, 1}, {1, 1}, {1, 0}, {0, 0}});
    return m;
}

ref_ptr<Material> physical(const vec4& base, float metallic, float roughness) {
    auto m = make<Material>(base);
    m->physical = true;
    m->pbr.metallic = metallic;
    m->pbr.roughness = roughness;
    return m;
}

// An n x n texture from f(u, v) in [0, 1]^2 giving RGBA in [0, 1].
template <typename F>
ref_ptr<Texture> texture(int n, F f) {
    std::vector<uint8_t> px;
    px.reserve(size_t(n) * size_t(n) * 4u);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const vec4 c = glm::clamp(f((x + 0.5f) / float(n), (y + 0.5f) / float(n)), 0.0f, 1.0f);
            for (int k = 0; k < 4; ++k) px.push_back(uint8_t(std::lround(c[k] * 255.0f)));
        }
    return make<Texture>(n, n, std::move(px));
}

// Bricks: 8 courses around the sphere, mortar between them; the height field's slope makes the normal map.
float brickHeight(float u, float v) {
    const float rows = 8.0f, cols = 16.0f;
    const float y = v * rows, row = std::floor(y);
    const float x = u * cols + (int(row) % 2 ? 0.5f : 0.0f);
    const float fx = x - std::floor(x), fy = y - row;
    const float edge = std::min(std::min(fx, 1.0f - fx) * 2.5f, std::min(fy, 1.0f - fy) * 1.25f);
    return std::clamp(edge * 8.0f, 0.0f, 1.0f);
}

ref_ptr<Material> brickMaterial() {
    constexpr int n = 256;
    auto m = physical(vec4(1.0f), 1.0f, 1.0f);
    m->texture = texture(n, [](float u, float v) {
        const float h = brickHeight(u, v), tint = 0.85f + 0.15f * std::sin(37.0f * std::floor(v * 8) + 11.0f * u);
        return h > 0.5f ? vec4(0.62f * tint, 0.27f * tint, 0.18f, 1) : vec4(0.75f, 0.74f, 0.7f, 1);
    });
    m->pbr.normal.texture = texture(n, [](float u, float v) {
        const float e = 1.0f / float(n);
        const float dx = (brickHeight(u + e, v) - brickHeight(u - e, v)) * 0.5f;
        const float dy = (brickHeight(u, v + e) - brickHeight(u, v - e)) * 0.5f;
        const vec3 t = glm::normalize(vec3(-dx * 4.0f, dy * 4.0f, 1.0f));  // glTF: +Y of the map is -v
        return vec4(t * 0.5f + 0.5f, 1.0f);
    });
    // Mortar rough and dielectric; bricks a little smoother; one band of metal.
    m->pbr.metallicRoughness.texture = texture(n, [](float u, float v) {
        const bool metal = v > 0.45f && v < 0.55f;
        return vec4(0.0f, metal ? 0.3f : brickHeight(u, v) > 0.5f ? 0.55f : 0.95f, metal ? 1.0f : 0.0f, 1.0f);
    });
    m->pbr.occlusion.texture =
        texture(n, [](float u, float v) { return vec4(0.35f + 0.65f * brickHeight(u, v), 0.0f, 0.0f, 1.0f); });
    m->pbr.emissive.texture = texture(n, [](float u, float v) {
        const bool lit = v > 0.2f && v < 0.25f && std::fmod(u * 16.0f, 1.0f) < 0.3f;
        return lit ? vec4(1.0f, 0.8f, 0.3f, 1.0f) : vec4(0.0f, 0.0f, 0.0f, 1.0f);
    });
    m->pbr.emissiveFactor = vec3(2.0f);
    return m;
}

ref_ptr<Node> placed(const ref_ptr<Node>& n, const dvec3& at) {
    auto t = make<Transform>(glm::translate(dmat4(1.0), at));
    t->addChild(n);
    return t;
}

}  // namespace

ref_ptr<Group> buildMaterials() {
    auto root = make<Group>();
    root->setName("materials");
    auto ball = makeSphereMesh(0.4f, 64, 32);
    const vec3 colours[3] = {{0.9f, 0.1f, 0.08f}, {0.95f, 0.64f, 0.54f}, {0.91f, 0.78f, 0.42f}};
    for (int row = 0; row < 3; ++row)
        for (int k = 0; k < 6; ++k) {
            const float roughness = 0.1f + 0.18f * float(k);
            auto g = make<Geometry>(ball, physical(vec4(colours[row], 1.0f), 0.5f * float(row), roughness));
            root->addChild(placed(g, dvec3(-2.5 + 1.0 * k, 0.4 + 1.0 * (2 - row), -1.5)));
        }
    root->addChild(placed(make<Geometry>(makeSphereMesh(1.0f, 128, 64), brickMaterial()), dvec3(3.4, 1.0, 0.3)));
    // The floor: a checker repeated 12 times across by its texture transform, single-sided, a little glossy.
    auto floorMat = physical(vec4(1.0f), 0.0f, 0.45f);
    floorMat->texture = texture(64, [](float u, float v) {
        const bool dark = (u < 0.5f) != (v < 0.5f);
        return dark ? vec4(0.2f, 0.2f, 0.22f, 1.0f) : vec4(0.8f, 0.8f, 0.76f, 1.0f);
    });
    floorMat->textureTransform = mat3(vec3(12, 0, 0), vec3(0, 12, 0), vec3(0, 0, 1));
    floorMat->doubleSided = false;
    root->addChild(make<Geometry>(quad({-6, 0, 6}, {6, 0, 6}, {6, 0, -6}, {-6, 0, -6}, {0, 1, 0}), floorMat));
    // Glass: blended, double-sided, in front of the middle spheres.
    auto glass = physical(vec4(0.55f, 0.8f, 0.95f, 0.3f), 0.0f, 0.05f);
    glass->blend = true;
    root->addChild(make<Geometry>(
        quad({-1.2f, 0, 0.8f}, {0.6f, 0, 0.8f}, {0.6f, 1.6f, 0.8f}, {-1.2f, 1.6f, 0.8f}, {0, 0, 1}), glass));
    return root;
}

}  // namespace scenes
