// pbr_cost: what a physical material costs per pixel against a classic one. A wall of quads fills the view at
// 1280x720 on OSMesa; the same frame is drawn with a classic lit material, a physical one with factors only, and a
// physical one with every map (base colour, metallic-roughness, normal, occlusion, emissive), each with and
// without 2 punctual lights, interleaved frame by frame (this machine's speed drifts for seconds at a time).
// Prints each's median frame, its ratio to the classic one and the extra nanoseconds per pixel.
//   pbr_cost [--frames F] [--size WxH]
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "testbed/Stats.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using namespace sg;

ref_ptr<Texture> noise(int n, int seed) {
    std::vector<uint8_t> px(size_t(n) * size_t(n) * 4u);
    uint32_t s = uint32_t(seed) * 2654435761u + 1u;
    for (size_t i = 0; i < px.size(); ++i) {
        s = s * 1664525u + 1013904223u;
        px[i] = i % 4 == 3 ? 255 : uint8_t(96 + (s >> 25));
    }
    return make<Texture>(n, n, std::move(px));
}

}  // namespace

int main(int argc, char** argv) try {
    int frames = 40, width = 1280, height = 720;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--frames" && i + 1 < argc)
            frames = std::atoi(argv[++i]);
        else if (a == "--size" && i + 1 < argc && std::sscanf(argv[++i], "%dx%d", &width, &height) == 2) {
        } else {
            std::fprintf(stderr, "usage: pbr_cost [--frames F] [--size WxH]\n");
            return 2;
        }
    }
    if (frames < 1 || width < 1 || height < 1) {
        std::fprintf(stderr, "pbr_cost: frames and sizes must be at least 1\n");
        return 2;
    }
    OsmesaContext context(width, height);
    Renderer renderer;
    Camera camera;
    // DrawItem matrices are relative to the eye (as the cull writes them): the eye at the origin, the wall at z = -5.
    camera.setLookAt(dvec3(0.0), dvec3(0.0, 0.0, -1.0), dvec3(0.0, 1.0, 0.0));
    camera.setPerspective(45.0, double(width) / height, 0.1, 100.0);
    camera.setViewport(width, height);
    renderer.setLight(DirectionalLight::sun(vec3(0.3f, 0.5f, 1.0f), vec3(0.3f), vec3(0.7f)));

    // 16 x 9 quads over a 12 x 7 wall: more than the view, every pixel drawn once.
    auto quad = make<Mesh>();
    quad->set({{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}}, std::vector<vec3>(4, {0, 0, 1}),
              {0, 1, 2, 0, 2, 3}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    quad->setSurface(std::vector<vec4>(4, vec4(1, 0, 0, 1)), {});
    auto classic = make<Material>(vec4(0.7f, 0.6f, 0.5f, 1.0f), noise(256, 1));
    classic->specular = 0.3f;
    auto plain = make<Material>(vec4(0.7f, 0.6f, 0.5f, 1.0f));
    plain->physical = true;
    plain->pbr.metallic = 0.3f;
    plain->pbr.roughness = 0.5f;
    auto full = make<Material>(vec4(0.7f, 0.6f, 0.5f, 1.0f), noise(256, 1));
    full->physical = true;
    full->pbr.metallicRoughness.texture = noise(256, 2);
    full->pbr.normal.texture = noise(256, 3);
    full->pbr.occlusion.texture = noise(256, 4);
    full->pbr.emissive.texture = noise(256, 5);
    full->pbr.emissiveFactor = vec3(0.2f);
    // The same with occlusion packed in the metallic-roughness texture (glTF's "ORM"): one sample for both.
    auto packed = make<Material>(vec4(0.7f, 0.6f, 0.5f, 1.0f), full->texture);
    packed->physical = true;
    packed->pbr = full->pbr;
    packed->pbr.occlusion.texture = packed->pbr.metallicRoughness.texture;
    struct Kind {
        const char* name;
        const Material* material;
        bool lights;
    };
    const Kind kinds[] = {
        {"classic (texture, highlight)", classic.get(), false}, {"physical, factors only", plain.get(), false},
        {"physical, factors, 2 lights", plain.get(), true},     {"physical, 5 maps", full.get(), false},
        {"physical, 5 maps, 2 lights", full.get(), true},       {"physical, 4 maps (ORM packed)", packed.get(), false}};
    constexpr int kKinds = int(sizeof kinds / sizeof kinds[0]);

    PunctualLight point;
    point.position = dvec3(1.0, 1.0, -3.0);
    point.intensity = 4.0f;
    PunctualLight spot = point;
    spot.type = PunctualLight::Type::Spot;
    spot.position = dvec3(-2.0, 0.0, -2.0);
    spot.direction = vec3(0.5f, 0.0f, -1.0f);

    std::vector<double> ms[kKinds];
    for (int f = -2; f < frames; ++f)  // two frames of each first: shader compiles and uploads
        for (int k = 0; k < kKinds; ++k) {
            DrawList list;
            for (int j = 0; j < 9; ++j)
                for (int i = 0; i < 16; ++i) {
                    DrawItem it;
                    it.mesh = quad.get();
                    it.material = kinds[k].material;
                    it.model = glm::mat4x3(
                        glm::scale(glm::translate(mat4(1.0f), vec3(-6.0f + 0.75f * float(i) + 0.375f,
                                                                   -3.5f + 0.78f * float(j) + 0.39f, -5.0f)),
                                   vec3(0.75f, 0.78f, 1.0f)));
                    list.add(it, 5.0f);
                }
            renderer.setPunctualLights(kinds[k].lights ? std::vector<PunctualLight>{point, spot}
                                                       : std::vector<PunctualLight>{});
            const auto t0 = std::chrono::steady_clock::now();
            renderer.draw(list, camera);
            renderer.finish();
            const double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            if (f >= 0) ms[k].push_back(t);
        }
    // The wall must cover the view: every pixel shaded, none left at the clear colour.
    const Image img = renderer.readColor();
    size_t clear = 0;
    const vec4 cc = Renderer::kClearColor;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        clear += std::abs(int(img.rgba[i]) - int(std::lround(cc.r * 255.0f))) <= 1 &&
                 std::abs(int(img.rgba[i + 1]) - int(std::lround(cc.g * 255.0f))) <= 1 &&
                 std::abs(int(img.rgba[i + 2]) - int(std::lround(cc.b * 255.0f))) <= 1;
    const double pixels = double(width) * height, base = stats::median(ms[0]);
    std::printf("pbr_cost: %zu of %.0f pixels left at the clear colour\n", clear, pixels);
    std::printf("pbr_cost: %dx%d, %d frames each, interleaved; median frame, ratio to classic, extra ns per pixel\n",
                width, height, frames);
    for (int k = 0; k < kKinds; ++k) {
        const double m = stats::median(ms[k]);
        std::printf("  %-30s %7.2f ms  %5.2fx  %+6.2f ns/pixel\n", kinds[k].name, m, m / base,
                    (m - base) * 1e6 / pixels);
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "pbr_cost: %s\n", e.what());
    return 1;
}
