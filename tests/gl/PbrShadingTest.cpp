// Physical materials against glTF 2.0's BRDF (Appendix B) evaluated here on the CPU, in double, from the spec's
// formulas: spheres and a plane of known materials under one directional light, the headlight, or a point and a
// spot light of KHR_lights_punctual, both as built and as a .glb written and read back. Every pixel's ray is cast
// into the triangles the renderer draws, the normal interpolated as the rasterizer does, the result written as
// sRGB and rounded to 8 bits.
#include "RenderUtil.h"
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/io/ImageIO.h"
#include "testbed/Materials.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>

using namespace sg;

namespace {

constexpr int kW = 256, kH = 192;
constexpr double kPi = 3.14159265358979323846;
const vec4 kClear(1.0f, 0.0f, 1.0f, 1.0f);  // magenta: no material below shades to it

ref_ptr<Mesh> floorMesh(float half, float y) {
    auto m = make<Mesh>();
    m->set({{-half, y, half}, {half, y, half}, {half, y, -half}, {-half, y, -half}}, std::vector<vec3>(4, {0, 1, 0}),
           {0, 1, 2, 0, 2, 3});
    return m;
}

ref_ptr<Material> physical(const vec3& base, float metallic, float roughness) {
    auto m = make<Material>(vec4(base, 1.0f));
    m->physical = true;
    m->pbr.metallic = metallic;
    m->pbr.roughness = roughness;
    return m;
}

// The light reaching a point: unit direction toward the light and irradiance at normal incidence.
using LightAt = std::function<void(const dvec3& p, std::vector<std::pair<dvec3, dvec3>>& out)>;

// glTF 2.0, Appendix B.3.5: f = (1 - F) c_diff / pi + F D V with c_diff = lerp(base, 0, metallic),
// F0 = lerp(0.04, base, metallic), alpha = roughness^2; the outgoing radiance is f E (n.l).
dvec3 brdfRadiance(const dvec3& n, const dvec3& v, const dvec3& l, const dvec3& e, const dvec3& base, double metallic,
                   double roughness) {
    const double nl = glm::dot(n, l);
    if (nl <= 0.0) return dvec3(0.0);
    const dvec3 h = glm::normalize(l + v);
    const double nv = std::abs(glm::dot(n, v)), nh = std::max(glm::dot(n, h), 0.0), vh = std::abs(glm::dot(v, h));
    const double alpha = roughness * roughness, a2 = alpha * alpha;
    const dvec3 cDiff = base * (1.0 - metallic);
    const dvec3 f0 = dvec3(0.04) * (1.0 - metallic) + base * metallic;
    const dvec3 fresnel = f0 + (dvec3(1.0) - f0) * std::pow(1.0 - vh, 5.0);
    const double dd = nh * nh * (a2 - 1.0) + 1.0;
    const double d = a2 / (kPi * dd * dd);
    const double vis =
        1.0 / ((nl + std::sqrt(a2 + (1.0 - a2) * nl * nl)) * (nv + std::sqrt(a2 + (1.0 - a2) * nv * nv)));
    const dvec3 f = (dvec3(1.0) - fresnel) * cDiff / kPi + fresnel * d * vis;
    return f * e * nl;
}

// IEC 61966-2-1, to 8 bits.
int srgb8(double c) {
    c = std::clamp(c, 0.0, 1.0);
    const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    return int(std::lround(s * 255.0));
}

struct Compared {
    size_t covered = 0, mismatched = 0;  // pixels covered in either image; of those, off by more than 2/255
    int worst = 0;
};

// Parameter: the scene as built, or as a .glb written by saveGltf and read back (what a user's file gives).
struct PbrShadingTest : ::testing::TestWithParam<bool> {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    ref_ptr<Group> root = make<Group>();
    Camera cam;

    PbrShadingTest() {
        cam.setLookAt(dvec3(0.0, 2.0, 7.0), dvec3(0.0, -0.3, 0.0), dvec3(0.0, 1.0, 0.0));
        cam.setPerspective(40.0, double(kW) / kH, 0.1, 100.0);
        cam.setViewport(kW, kH);
        const std::pair<dvec3, ref_ptr<Material>> spheres[] = {
            {{-2.1, 0.0, 0.0}, physical({0.8f, 0.15f, 0.1f}, 0.0f, 0.5f)},    // dielectric
            {{0.0, 0.0, 0.0}, physical({0.95f, 0.75f, 0.35f}, 1.0f, 0.45f)},  // metal
            {{2.1, 0.0, 0.0}, physical({0.2f, 0.5f, 0.9f}, 0.5f, 0.8f)},      // between, rough
        };
        auto ball = scenes::makeSphereMesh(0.9f, 96, 48);
        for (const auto& [at, mat] : spheres) {
            auto t = make<Transform>(glm::translate(dmat4(1.0), at));
            t->addChild(make<Geometry>(ball, mat));
            root->addChild(t);
        }
        root->addChild(make<Geometry>(floorMesh(6.0f, -0.9f), physical({0.6f, 0.6f, 0.55f}, 0.0f, 0.9f)));
        if (GetParam()) {
            // One file per process: ctest runs the tests side by side.
            const std::string file = ::testing::TempDir() + "pbr_shading_" + std::to_string(getpid()) + ".glb";
            saveGltf(*root, file);
            root = make<Group>();
            root->addChild(loadGltf(file).root);
        }
    }

    // Draws the scene and compares every pixel with the CPU's evaluation under `lights`.
    Compared renderAndCompare(const LightAt& lights, const char* name) {
        Scene scene(root);
        scene.update();
        const Image img = testutil::drawScene(renderer, scene, cam, true, kClear);
        if (std::getenv("SGKIT_TEST_IMAGES")) savePng(std::string(name) + ".png", img);

        const dmat4 toWorld = glm::inverse(cam.projection() * cam.view());
        IntersectTraversal rays;
        std::vector<std::pair<dvec3, dvec3>> ls;
        Compared c;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const uint8_t* px = &img.rgba[(size_t(y) * kW + size_t(x)) * 4u];
                const bool drawn = !(px[0] == 255 && px[1] == 0 && px[2] == 255);
                // The pixel's centre, rows counted from the top as readColor() gives them.
                const dvec2 ndc(2.0 * (x + 0.5) / kW - 1.0, 1.0 - 2.0 * (y + 0.5) / kH);
                const dvec4 far = toWorld * dvec4(ndc, 1.0, 1.0);
                Hit hit;
                const bool hitSomething =
                    rays.intersect(scene, Ray{cam.eye(), glm::normalize(dvec3(far) / far.w - cam.eye())}, {}, hit);
                if (!drawn && !hitSomething) continue;
                ++c.covered;
                if (drawn != hitSomething) {
                    ++c.mismatched;
                    continue;
                }
                const Mesh& mesh = *hit.geometry->mesh();
                const Material& mat = *hit.geometry->material();
                const uint32_t t = hit.primitive;
                const auto& ns = mesh.normals();
                const dvec3 n =
                    glm::normalize((1.0 - hit.u - hit.v) * dvec3(ns[mesh.index(3 * t)]) +
                                   hit.u * dvec3(ns[mesh.index(3 * t + 1)]) + hit.v * dvec3(ns[mesh.index(3 * t + 2)]));
                const dvec3 v = glm::normalize(cam.eye() - hit.point);
                dvec3 rgb(0.0);
                ls.clear();
                lights(hit.point, ls);
                for (const auto& [l, e] : ls)
                    rgb += brdfRadiance(n, v, l, e, dvec3(mat.baseColor), mat.pbr.metallic, mat.pbr.roughness);
                int diff = 0;
                for (int k = 0; k < 3; ++k) diff = std::max(diff, std::abs(int(px[k]) - srgb8(rgb[k])));
                c.worst = std::max(c.worst, diff);
                if (diff > 2) ++c.mismatched;
            }
        return c;
    }
};

}  // namespace

TEST_P(PbrShadingTest, DirectionalLightMatchesAppendixB) {
    // A sun and no sky or ground: what the pixels show is the BRDF alone.
    const vec3 toSun = glm::normalize(vec3(0.5f, 0.8f, 0.45f)), color(0.9f, 0.85f, 0.8f);
    renderer.setLight(DirectionalLight::sun(toSun, vec3(0.0f), color));
    const Compared c = renderAndCompare(
        [&](const dvec3&, auto& out) {
            out.push_back({glm::normalize(dvec3(toSun)), kPi * dvec3(color)});
        },
        "pbr_sun");
    EXPECT_GT(c.covered, size_t(kW * kH / 3));  // the spheres and the floor fill a good part of the picture
    EXPECT_LE(c.mismatched, c.covered / 1000) << c.mismatched << " of " << c.covered << ", worst " << c.worst;
    std::printf("%zu pixels covered, %zu off by more than 2/255, worst %d/255\n", c.covered, c.mismatched, c.worst);
}

TEST_P(PbrShadingTest, HeadlightShinesFromTheEye) {
    // No sun set: the default light is at the eye, for every fragment along its view ray.
    DirectionalLight head;
    head.ambient = vec3(0.0f);
    head.color = vec3(0.8f, 0.8f, 0.75f);
    renderer.setLight(head);
    const dvec3 eye = cam.eye();
    const Compared c = renderAndCompare(
        [&](const dvec3& p, auto& out) {
            out.push_back({glm::normalize(eye - p), kPi * dvec3(head.color)});
        },
        "pbr_headlight");
    EXPECT_GT(c.covered, size_t(kW * kH / 3));
    EXPECT_LE(c.mismatched, c.covered / 1000) << c.mismatched << " of " << c.covered << ", worst " << c.worst;
}

TEST_P(PbrShadingTest, PointAndSpotLightsMatchKhrLightsPunctual) {
    // The sun dark: a point light with a range and a spot whose cone edge crosses the floor.
    renderer.setLight(DirectionalLight::sun(vec3(0.0f, 1.0f, 0.0f), vec3(0.0f), vec3(0.0f)));
    PunctualLight point;
    point.type = PunctualLight::Type::Point;
    point.position = dvec3(-1.0, 1.5, 1.5);
    point.color = vec3(1.0f, 0.9f, 0.7f);
    point.intensity = 6.0f;
    point.range = 6.0f;
    PunctualLight spot;
    spot.type = PunctualLight::Type::Spot;
    spot.position = dvec3(2.5, 3.0, 1.0);
    spot.direction = glm::normalize(vec3(-0.3f, -1.0f, -0.2f));
    spot.color = vec3(0.6f, 0.8f, 1.0f);
    spot.intensity = 12.0f;
    spot.innerConeAngle = 0.3f;
    spot.outerConeAngle = 0.6f;
    renderer.setPunctualLights({point, spot});
    // KHR_lights_punctual: intensity / d^2, times the recommended range window clamp(1 - (d / range)^4, 0, 1)^1
    // as written, and for a spot the smooth cone clamp((cos - cos outer) / (cos inner - cos outer), 0, 1)^2.
    const auto lights = [&](const dvec3& p, auto& out) {
        for (const PunctualLight& l : {point, spot}) {
            const dvec3 toLight = l.position - p;
            const double d2 = glm::dot(toLight, toLight);
            const dvec3 dir = toLight / std::sqrt(d2);
            double e = l.intensity / d2;
            if (l.range > 0.0f) e *= std::clamp(1.0 - std::pow(d2 / (double(l.range) * l.range), 2.0), 0.0, 1.0);
            if (l.type == PunctualLight::Type::Spot) {
                const double cosOuter = std::cos(double(l.outerConeAngle)),
                             cosInner = std::cos(double(l.innerConeAngle));
                const double cd = glm::dot(dvec3(glm::normalize(l.direction)), -dir);
                const double s = std::clamp((cd - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
                e *= s * s;
            }
            out.push_back({dir, e * dvec3(l.color)});
        }
    };
    const Compared c = renderAndCompare(lights, "pbr_punctual");
    EXPECT_GT(c.covered, size_t(kW * kH / 3));
    EXPECT_LE(c.mismatched, c.covered / 1000) << c.mismatched << " of " << c.covered << ", worst " << c.worst;
    std::printf("%zu pixels covered, %zu off by more than 2/255, worst %d/255\n", c.covered, c.mismatched, c.worst);
}

INSTANTIATE_TEST_SUITE_P(BuiltOrRead, PbrShadingTest, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "ThroughGlb" : "InMemory"; });
