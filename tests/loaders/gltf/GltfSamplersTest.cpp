// glTF samplers: read into Texture::sampler (a Texture per image and sampler), bad values warned, written back by
// saveGltf only where they differ from the default.
#include "GltfTestUtil.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace sg;
using gltftest::Doc;

namespace {

using Wrap = Sampler::Wrap;
using Filter = Sampler::Filter;

// A 1x1 RGBA PNG.
const char* const kPng =
    "data:image/png;base64,"
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4nGP43+DwHwAHAAK/K9fH4gAAAABJRU5ErkJggg==";

// n root nodes, node k drawing the one triangle with material k, whose base colour texture is texture k; one image.
Doc texturedDoc(int n, const std::string& textures, const std::string& samplers) {
    std::string nodes, meshes, materials;
    for (int k = 0; k < n; ++k) {
        const std::string sep = k ? ", " : "", ks = std::to_string(k);
        nodes += sep + ks;
        meshes += sep + R"({"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": )" + ks + "}]}";
        materials += sep + R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": )" + ks + "}}}";
    }
    std::string roots;
    for (int k = 0; k < n; ++k) roots += std::string(k ? ", " : "") + R"({"mesh": )" + std::to_string(k) + "}";
    Doc d;
    d.json = R"("scenes": [{"nodes": [)" + nodes + R"(]}], "nodes": [)" + roots + R"(], "meshes": [)" + meshes +
             R"(], "materials": [)" + materials + R"(], "images": [{"uri": ")" + kPng + R"("}], "textures": )" +
             textures + R"(, "samplers": )" + samplers;
    return d;
}

const Geometry* firstGeometry(const Node& n) {
    if (n.kind() == NodeKind::Geometry) return static_cast<const Geometry*>(&n);
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Geometry* g = firstGeometry(*n.child(i))) return g;
    return nullptr;
}

// The base colour texture drawn by root node k.
const Texture* textureOf(const GltfScene& s, size_t k) {
    const Geometry* g = k < s.root->numChildren() ? firstGeometry(*s.root->child(k)) : nullptr;
    return g && g->material() ? g->material()->texture.get() : nullptr;
}

Sampler sampler(Wrap s, Wrap t, Filter mag, Filter min) {
    Sampler x;
    x.wrapS = s;
    x.wrapT = t;
    x.magFilter = mag;
    x.minFilter = min;
    return x;
}

bool hasWarning(const GltfScene& s, const std::string& part) {
    for (const std::string& w : s.warnings)
        if (w.find(part) != std::string::npos) return true;
    return false;
}

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_samplers_" + name; }

}  // namespace

TEST(GltfSamplers, EveryWrapAndFilterIsRead) {
    const Doc d = texturedDoc(8,
                              R"([{"source": 0, "sampler": 0}, {"source": 0, "sampler": 1}, {"source": 0, "sampler": 2},
            {"source": 0, "sampler": 3}, {"source": 0, "sampler": 4}, {"source": 0, "sampler": 5},
            {"source": 0, "sampler": 6}, {"source": 0}])",
                              R"([{"wrapS": 33071, "wrapT": 33648, "magFilter": 9728, "minFilter": 9728},
            {"wrapS": 33648, "wrapT": 10497, "magFilter": 9729, "minFilter": 9729},
            {"wrapS": 10497, "wrapT": 33071, "minFilter": 9984}, {"minFilter": 9985}, {"minFilter": 9986},
            {"minFilter": 9987}, {}])");
    const GltfScene s = d.load();
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    // Absent: REPEAT, and LINEAR / LINEAR_MIPMAP_LINEAR.
    const Sampler want[8] = {
        sampler(Wrap::ClampToEdge, Wrap::MirroredRepeat, Filter::Nearest, Filter::Nearest),
        sampler(Wrap::MirroredRepeat, Wrap::Repeat, Filter::Linear, Filter::Linear),
        sampler(Wrap::Repeat, Wrap::ClampToEdge, Filter::Linear, Filter::NearestMipmapNearest),
        sampler(Wrap::Repeat, Wrap::Repeat, Filter::Linear, Filter::LinearMipmapNearest),
        sampler(Wrap::Repeat, Wrap::Repeat, Filter::Linear, Filter::NearestMipmapLinear),
        sampler(Wrap::Repeat, Wrap::Repeat, Filter::Linear, Filter::LinearMipmapLinear),
        Sampler{},
        Sampler{},
    };
    for (size_t k = 0; k < 8; ++k) {
        const Texture* t = textureOf(s, k);
        ASSERT_NE(t, nullptr) << "texture " << k;
        EXPECT_TRUE(t->sampler == want[k]) << "texture " << k;
        EXPECT_EQ(t->rgba(), textureOf(s, 0)->rgba()) << "texture " << k;  // one image under them all
    }
    EXPECT_NE(textureOf(s, 0), textureOf(s, 1));  // one image, two samplers: two Textures
    EXPECT_EQ(textureOf(s, 5), textureOf(s, 6));  // equal samplers (given or absent) share one
    EXPECT_EQ(textureOf(s, 6), textureOf(s, 7));
}

TEST(GltfSamplers, ValuesOutsideTheEnumsAreWarnedAndTheDefaultsTaken) {
    const Doc d = texturedDoc(1, R"([{"source": 0, "sampler": 0}])",
                              R"([{"wrapS": 12345, "wrapT": 0, "magFilter": 9984, "minFilter": 1}])");
    const GltfScene s = d.load();
    const Texture* t = textureOf(s, 0);
    ASSERT_NE(t, nullptr);
    EXPECT_TRUE(t->sampler == Sampler{});
    EXPECT_TRUE(hasWarning(s, "samplers[0].wrapS: 12345"));
    EXPECT_TRUE(hasWarning(s, "samplers[0].wrapT: 0"));
    EXPECT_TRUE(hasWarning(s, "samplers[0].magFilter: 9984"));  // a mipmap filter cannot magnify
    EXPECT_TRUE(hasWarning(s, "samplers[0].minFilter: 1"));
    EXPECT_TRUE(hasWarning(s, "REPEAT used"));
    EXPECT_EQ(s.warnings.size(), 4u);
}

TEST(GltfSamplers, SaveWritesADistinctSamplerOnceAndLoadReadsItBack) {
    // Four textures: a (clamp, nearest), b (default), c (mirrored, another min filter), d (a's pixels under c's
    // sampler). Each material's base colour tells them apart after the round trip.
    auto mesh = make<Mesh>();
    mesh->set({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, {0, 1, 2}, {{0, 0}, {1, 0}, {0, 1}});
    auto tex = [](uint8_t r, const Sampler& s) {
        auto t = make<Texture>(1, 1, std::vector<uint8_t>{r, 0, 0, 255});
        t->sampler = s;
        return t;
    };
    const Sampler clamp = sampler(Wrap::ClampToEdge, Wrap::ClampToEdge, Filter::Nearest, Filter::Nearest);
    const Sampler mirrored = sampler(Wrap::MirroredRepeat, Wrap::Repeat, Filter::Linear, Filter::LinearMipmapNearest);
    const ref_ptr<Texture> textures[4] = {tex(10, clamp), tex(20, Sampler{}), tex(30, mirrored), tex(10, mirrored)};
    auto root = make<Group>();
    for (int k = 0; k < 4; ++k)
        root->addChild(make<Geometry>(mesh, make<Material>(vec4(0.25f * float(k), 1, 1, 1), textures[k])));
    for (const char* ext : {".gltf", ".glb"}) {
        const std::string path = tempPath(std::string("roundtrip") + ext);
        saveGltf(*root, path);
        const GltfScene s = loadGltf(path);
        int found = 0;
        std::vector<const Node*> stack{s.root.get()};
        while (!stack.empty()) {
            const Node* n = stack.back();
            stack.pop_back();
            for (size_t i = 0; i < n->numChildren(); ++i) stack.push_back(n->child(i));
            if (n->kind() != NodeKind::Geometry) continue;
            const Material* m = static_cast<const Geometry*>(n)->material();
            ASSERT_TRUE(m && m->texture) << ext;
            const int k = int(std::lround(m->baseColor.r * 4.0f));
            ASSERT_TRUE(k >= 0 && k < 4) << ext;
            EXPECT_TRUE(m->texture->sampler == textures[k]->sampler) << ext << " texture " << k;
            EXPECT_EQ(m->texture->rgba(), textures[k]->rgba()) << ext << " texture " << k;
            ++found;
        }
        EXPECT_EQ(found, 4) << ext;
    }
    // The text form: two samplers (clamp's and mirrored's), none on the default texture, a's and d's pixels once.
    std::ifstream in(tempPath("roundtrip.gltf"));
    const nlohmann::json j = nlohmann::json::parse(std::string(std::istreambuf_iterator<char>(in), {}));
    ASSERT_TRUE(j.contains("samplers"));
    EXPECT_EQ(j["samplers"].size(), 2u);
    EXPECT_EQ(j["textures"].size(), 4u);
    EXPECT_EQ(j["images"].size(), 3u);
    int withoutSampler = 0;
    for (const auto& t : j["textures"]) withoutSampler += t.contains("sampler") ? 0 : 1;
    EXPECT_EQ(withoutSampler, 1);
    for (const auto& gs : j["samplers"]) {
        EXPECT_TRUE(gs["wrapS"] == 33071 || gs["wrapS"] == 33648);
        const bool clamped = gs["wrapS"] == 33071;
        EXPECT_EQ(gs["magFilter"], clamped ? 9728 : 9729);
        EXPECT_EQ(gs["minFilter"], clamped ? 9728 : 9985);
    }
}

TEST(GltfSamplers, DefaultTexturesAreWrittenWithoutSamplers) {
    auto mesh = make<Mesh>();
    mesh->set({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, {0, 1, 2}, {{0, 0}, {1, 0}, {0, 1}});
    auto root = make<Group>();
    root->addChild(
        make<Geometry>(mesh, make<Material>(vec4(1), make<Texture>(1, 1, std::vector<uint8_t>{1, 2, 3, 4}))));
    const std::string path = tempPath("default.gltf");
    saveGltf(*root, path);
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(std::string(std::istreambuf_iterator<char>(in), {}));
    EXPECT_FALSE(j.contains("samplers"));
    ASSERT_EQ(j["textures"].size(), 1u);
    EXPECT_FALSE(j["textures"][0].contains("sampler"));
}
