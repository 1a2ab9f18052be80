// sgbench load: the glTF loader against tinygltf's own parse of the same .glb. The file (boxes split into
// fine grids, distinct meshes, about --size-mb of vertex and index data) is written once into /tmp; then
// tinygltf's LoadBinaryFromFile and sg::loadGltf run alternately in one process, medians compared.
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sgbench/Bench.h"

#include <tiny_gltf.h>

#include <sys/stat.h>
#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace bench {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

size_t meshBytes(const sg::Mesh& m) {
    return m.positions().size() * 12 + m.normals().size() * 12 + m.uvs().size() * 8 + m.indices16().size() * 2 +
           m.indices32().size() * 4;
}

// Distinct meshes (a box of 6 x 90 x 90 quads each, ~2.2 MB) until `bytes` of buffer data.
sg::ref_ptr<sg::Group> buildScene(size_t bytes, size_t& meshes, size_t& triangles) {
    auto root = sg::make<sg::Group>();
    auto mat = sg::make<sg::Material>();
    size_t total = 0;
    meshes = triangles = 0;
    for (int i = 0; total < bytes; ++i) {
        auto mesh = sg::makeBoxMesh(sg::dvec3(-1.0 - 0.01 * i), sg::dvec3(1.0), 90);
        total += meshBytes(*mesh);
        triangles += mesh->triangleCount();
        ++meshes;
        auto t = sg::make<sg::Transform>(glm::translate(sg::dmat4(1.0), sg::dvec3(3.0 * i, 0, 0)));
        t->addChild(sg::make<sg::Geometry>(mesh, mat));
        root->addChild(t);
    }
    return root;
}
}  // namespace

int runLoad(const Args& a) {
    if (a.flag("features")) return runLoadFeatures(a);
    const long sizeMb = a.num("size-mb", 100), runs = a.num("runs", 5);
    if (sizeMb < 1 || runs < 1) throw std::invalid_argument("sgbench load: --size-mb and --runs must be at least 1");
    const std::string path = a.str("file", "/tmp/sgbench_load_" + std::to_string(sizeMb) + "mb.glb");
    size_t meshes = 0, triangles = 0;
    const auto tg = Clock::now();
    {
        auto scene = buildScene(size_t(sizeMb) << 20, meshes, triangles);
        sg::saveGltf(*scene, path);
    }
    const double writeMs = msSince(tg);
    struct stat st {};
    ::stat(path.c_str(), &st);

    std::vector<double> tiny, ours;
    size_t loadedGeometries = 0;
    for (long r = 0; r < runs; ++r) {
        {
            tinygltf::TinyGLTF parser;
            tinygltf::Model model;
            std::string err, warn;
            const auto t0 = Clock::now();
            const bool ok = parser.LoadBinaryFromFile(&model, &err, &warn, path);
            tiny.push_back(msSince(t0));
            if (!ok) throw std::runtime_error("sgbench load: tinygltf: " + err);
        }
        {
            const auto t0 = Clock::now();
            const sg::GltfScene s = sg::loadGltf(path);
            ours.push_back(msSince(t0));
            loadedGeometries = s.root->numChildren();
        }
    }
    if (loadedGeometries != meshes) throw std::runtime_error("sgbench load: the loaded scene has the wrong size");
    const double t = median(tiny), o = median(ours);
    Json j;
    j.add("command", "load").add("file", path).add("file_mb", double(st.st_size) / (1024.0 * 1024.0));
    j.addInt("meshes", long(meshes)).addInt("triangles", long(triangles)).addInt("runs", runs);
    j.add("write_ms", writeMs).add("tinygltf_ms_median", t).add("sgkit_ms_median", o).add("ratio", o / t);
    j.add("tinygltf_ms_min", percentile(tiny, 0.0)).add("sgkit_ms_min", percentile(ours, 0.0));
    j.print(a);
    return 0;
}

}  // namespace bench
