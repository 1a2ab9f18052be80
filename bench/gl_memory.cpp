// gl_memory: where a headless program's resident memory goes when the renderer draws many small meshes. Prints
// the resident set after each phase: the OSMesa context, the renderer, its first frame (one tiny mesh: the
// shader variants llvmpipe compiles, its depth buffer and bins), N meshes uploaded and drawn (K materials),
// the same frame again, all released, and N new meshes drawn in their place (what a paged level does).
//   gl_memory [--meshes N] [--div D] [--materials K] [--size WxH] [--frames F] [--far F]
// A mesh is a box with each face split into D x D quads: 6 (D + 1)^2 vertices, 12 D^2 triangles. The near plane
// is at 1; a far plane beyond 10,000 draws with the renderer's reverse-Z framebuffer (as the map does).
// "files" are resident pages of mapped files (the libraries' code: llvmpipe compiling its shaders pages in
// much of LLVM's), "anonymous" the rest (heap, GL buffers, framebuffers).
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <malloc.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace sg;

long residentKb() {
    std::ifstream in("/proc/self/statm");
    long pages = 0, resident = 0;
    in >> pages >> resident;
    return resident * sysconf(_SC_PAGESIZE) / 1024;
}

// Resident pages backed by files (the libraries' code, LLVM's above all) and anonymous ones (heap, buffers).
long statusKb(const char* field) {
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);)
        if (line.compare(0, std::strlen(field), field) == 0) return std::atol(line.c_str() + std::strlen(field));
    return 0;
}

long heapKb() {
    const struct mallinfo2 m = mallinfo2();
    return long((m.uordblks + m.hblkhd) / 1024);
}

long last = 0;
void phase(const char* what) {
    const long r = residentKb();
    std::printf("%-34s resident %7ld kB (%+7ld): files %7ld, anonymous %7ld; malloc in use %7ld kB\n", what, r,
                last ? r - last : 0, statusKb("RssFile:"), statusKb("RssAnon:"), heapKb());
    last = r;
}

struct Frame {
    std::vector<ref_ptr<Mesh>> meshes;
    std::vector<ref_ptr<Material>> materials;
    DrawList list;
};

// n boxes on a grid filling the view (eye at z = 10 looking down -z), materials in turn, sorted by state as the
// cull sorts them.
void build(Frame& f, int n, int div, int materials, int seed) {
    f.meshes.clear();
    f.list.clear();
    f.materials.clear();
    for (int k = 0; k < materials; ++k)
        f.materials.push_back(make<Material>(
            vec4(0.2f + 0.6f * float((k * 37 + seed) % 11) / 10.0f, 0.5f, 0.3f + 0.05f * float(k % 7), 1.0f)));
    int side = 1;
    while (side * side < n) ++side;
    const double cell = 8.0 / side;
    for (int i = 0; i < n; ++i) {
        const double x = -4.0 + cell * (i % side + 0.5), y = -4.0 + cell * (i / side + 0.5);
        // Boxes of slightly different sizes: no two meshes alike, as in a map.
        const double h = 0.3 * cell * (1.0 + 0.001 * ((i + seed) % 97));
        f.meshes.push_back(makeBoxMesh(dvec3(-h, -h, -h), dvec3(h, h, h), div));
        DrawItem it;
        it.mesh = f.meshes.back().get();
        it.material = f.materials[size_t(i % materials)].get();
        it.model = glm::mat4x3(glm::translate(mat4(1.0f), vec3(float(x), float(y), -10.0f)));
        f.list.add(it, 10.0f);
    }
    f.list.sort();
}

}  // namespace

int main(int argc, char** argv) try {
    int n = 1000, div = 2, materials = 8, width = 1280, height = 720, frames = 2;
    double far = 100.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool more = i + 1 < argc;
        if (a == "--meshes" && more)
            n = std::atoi(argv[++i]);
        else if (a == "--div" && more)
            div = std::atoi(argv[++i]);
        else if (a == "--materials" && more)
            materials = std::atoi(argv[++i]);
        else if (a == "--frames" && more)
            frames = std::atoi(argv[++i]);
        else if (a == "--far" && more)
            far = std::atof(argv[++i]);
        else if (a == "--size" && more && std::sscanf(argv[++i], "%dx%d", &width, &height) == 2) {
        } else {
            std::fprintf(
                stderr,
                "usage: gl_memory [--meshes N] [--div D] [--materials K] [--size WxH] [--frames F] [--far F]\n");
            return 2;
        }
    }
    if (n < 1 || div < 1 || materials < 1 || frames < 1 || width < 1 || height < 1 || !(far > 20.0)) {
        std::fprintf(stderr, "gl_memory: every count must be at least 1, the far plane beyond 20\n");
        return 2;
    }
    phase("start");
    OsmesaContext context(width, height);
    phase("context");
    Renderer renderer;
    if (renderer.softwareRasterizer()) keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    phase("renderer (sgmap's empty program)");
    Camera camera;
    camera.setLookAt(dvec3(0.0), dvec3(0.0, 0.0, -1.0), dvec3(0.0, 1.0, 0.0));
    camera.setPerspective(45.0, double(width) / height, 1.0, far);
    camera.setViewport(width, height);

    Frame tiny;
    build(tiny, 1, 1, 1, 0);
    renderer.draw(tiny.list, camera);
    renderer.finish();
    phase("first frame (one box)");

    Frame f;
    build(f, n, div, materials, 1);
    size_t geometry = 0;
    for (const auto& m : f.meshes)
        geometry += m->positions().size() * 24 + m->indexCount() * (m->indices16().empty() ? 4 : 2);
    std::printf("%d meshes of %zu vertices, %u triangles; %zu kB of vertex and index data\n", n,
                f.meshes[0]->positions().size(), f.meshes[0]->triangleCount(), geometry / 1024);
    for (int k = 0; k < frames; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        renderer.draw(f.list, camera);
        renderer.finish();
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        const std::string what = "frame " + std::to_string(k + 1) + " (" +
                                 std::to_string(renderer.lastStats().drawCalls) + " draws, " + std::to_string(int(ms)) +
                                 " ms)";
        phase(what.c_str());
    }
    Frame none;
    renderer.draw(none.list, camera);
    renderer.releaseUnused();
    f = Frame{};
    malloc_trim(0);
    phase("released, trimmed");
    Frame g;
    build(g, n, div, materials, 2);
    for (int k = 0; k < frames; ++k) {
        renderer.draw(g.list, camera);
        renderer.finish();
    }
    phase("new meshes drawn in their place");
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "gl_memory: %s\n", e.what());
    return 1;
}
