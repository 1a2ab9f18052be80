// The factory through gltfpack and back: saved as .glb, packed with quantization and meshopt compression (-cc)
// and with compression alone (-cc -noq), loaded, and drawn from the same views as the scene in memory. Packing
// moves vertices by its quantization step and rewrites normals, so pixels are compared with a tolerance.
#include "OutsideTools.h"
#include "RenderUtil.h"
#include "loaders/gltf/Gltf.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "sg/scene/internal/DistinctGeometries.h"
#include "testbed/Factory.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unordered_set>

using namespace sg;
namespace fs = std::filesystem;

namespace {

constexpr int kW = 256, kH = 144;
// A channel differing by more than this many levels makes a pixel count as differing.
constexpr int kLevels = 24;

// Each mesh once, however many Geometries draw it.
size_t meshBytes(const Node& root) {
    std::unordered_set<const Mesh*> seen;
    size_t bytes = 0;
    forEachDistinctGeometry(root, [&](const Geometry& g) {
        if (g.mesh() && seen.insert(g.mesh()).second) bytes += g.mesh()->bytes();
    });
    return bytes;
}

// gltfpack keeps named nodes (-kn) and their extras (-ke), where sgkit's LODs, Switches and Billboards travel;
// unnamed ones it merges or drops.
void nameEveryNode(Node& root) {
    std::unordered_set<const Node*> seen;
    std::vector<Node*> stack{&root};
    while (!stack.empty()) {
        Node* n = stack.back();
        stack.pop_back();
        if (!seen.insert(n).second) continue;
        if (n->name().empty()) n->setName("n" + std::to_string(seen.size()));
        for (size_t i = 0; i < n->numChildren(); ++i)
            if (Node* c = n->child(i)) stack.push_back(c);
    }
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Packed {
    std::string options;
    double worstFraction;  // of the pixels of one view that may differ by more than kLevels
};

}  // namespace

TEST(GltfPackImage, TheFactoryPackedByGltfpackDrawsAsTheOriginal) {
#ifndef SGKIT_GLTFPACK
    GTEST_SKIP() << "no SGKIT_GLTFPACK: build the tiles-tools target";
#else
    if (!fs::exists(SGKIT_GLTFPACK)) SG_SKIP_OR_FAIL(SGKIT_GLTFPACK << " absent: build the tiles-tools target");
    const scenes::Factory f = scenes::buildFactory();
    const std::string dir = ::testing::TempDir(), in = dir + "sgkit_pack_factory.glb";
    nameEveryNode(*f.root);
    saveGltf(*f.root, in);
    std::vector<Camera> views;
    for (int k = 0; k < 6; ++k)
        views.push_back(scenes::factoryOrbitCamera(k * scenes::kFactoryOrbitFrames / 6, kW, kH));
    views.push_back(scenes::factoryWorkshopCamera(f, 0, kW, kH));

    OsmesaContext context(kW, kH);
    Renderer renderer;
    std::vector<Image> original;
    for (const Camera& c : views) original.push_back(testutil::drawGraph(renderer, f.root, c));
    std::printf("factory: %zu bytes as .glb, %zu bytes of meshes in memory\n", size_t(fs::file_size(in)),
                meshBytes(*f.root));

    // Measured: 0.40% of the pixels of the worst view with quantization (edges moved by its step, 14 bits over a
    // mesh's extent), 0.01% without.
    for (const Packed& p : {Packed{"-cc", 0.01}, Packed{"-cc -noq", 0.002}}) {
        const std::string out = dir + "sgkit_pack_factory_out.glb", log = dir + "sgkit_pack.log";
        const std::string cmd = std::string("'") + SGKIT_GLTFPACK + "' -i '" + in + "' -o '" + out + "' " + p.options +
                                " -ke -kn > '" + log + "' 2>&1";
        ASSERT_EQ(std::system(cmd.c_str()), 0) << readText(log);
        const std::string bytes = readText(out);  // the extensions under test are in use
        EXPECT_NE(bytes.find("\"EXT_meshopt_compression\""), std::string::npos) << p.options;
        EXPECT_EQ(bytes.find("\"KHR_mesh_quantization\"") != std::string::npos, p.options == "-cc") << p.options;
        const GltfScene packed = loadGltf(out);
        double worst = 0.0;
        for (size_t k = 0; k < views.size(); ++k) {
            const Image img = testutil::drawGraph(renderer, packed.root, views[k]);
            const double fraction = double(countDifferingPixels(original[k], img, kLevels)) / double(kW * kH);
            worst = std::max(worst, fraction);

            EXPECT_LE(fraction, p.worstFraction) << p.options << " view " << k;
        }
        std::printf(
            "gltfpack %s: %zu bytes, %zu bytes of meshes in memory, worst view %.4f of pixels differ by "
            "more than %d levels\n",
            p.options.c_str(), size_t(fs::file_size(out)), meshBytes(*packed.root), worst, kLevels);
    }
#endif
}
