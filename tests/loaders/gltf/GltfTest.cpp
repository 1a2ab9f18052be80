// glTF loader and writer: round trips of every node kind, glTF features from hand-written files, one
// malformed file per error class (exact JSON path, reason), random corruption, progress.
#include "GltfTestUtil.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Occluder.h"
#include "sg/scene/Scene.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>

using namespace sg;
using namespace gltftest;

namespace {

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_gltf_" + name; }

std::vector<unsigned char> readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(f), {});
}

void writeFile(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

GltfScene roundTrip(const Node& root, const std::string& ext) {
    const std::string path = tempPath("roundtrip" + ext);
    saveGltf(root, path);
    return loadGltf(path);
}

// The same world bounds, entry by entry, in the flat images of both graphs.
void expectSameBounds(const ref_ptr<Node>& a, const ref_ptr<Node>& b) {
    Scene sa(a), sb(b);
    sa.update();
    sb.update();
    const FlatImage& ia = sa.image();
    const FlatImage& ib = sb.image();
    ASSERT_EQ(ia.size(), ib.size());
    for (size_t i = 0; i < ia.size(); ++i) {
        ASSERT_EQ(ia.kind[i], ib.kind[i]) << "entry " << i;
        ASSERT_EQ(ia.end[i], ib.end[i]) << "entry " << i;
        const Box ba = ia.box(i), bb = ib.box(i);
        ASSERT_EQ(ba.min, bb.min) << "entry " << i;
        ASSERT_EQ(ba.max, bb.max) << "entry " << i;
    }
}

}  // namespace

TEST(Gltf, EveryNodeKindSurvivesARoundTrip) {
    for (const char* ext : {".glb", ".gltf"}) {
        SCOPED_TRACE(ext);
        ref_ptr<Group> root = allKindsScene();
        const GltfScene loaded = roundTrip(*root, ext);
        EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
        expectSameGraph(*root, *loaded.root);
        expectSameBounds(root, loaded.root);
    }
}

TEST(Gltf, RandomScenesSurviveARoundTrip) {
    for (uint64_t seed : {1u, 2u, 3u, 4u}) {
        SCOPED_TRACE(seed);
        ref_ptr<Group> root = scenes::buildRandomScene(seed);
        const GltfScene loaded = roundTrip(*root, seed % 2 ? ".glb" : ".gltf");
        expectSameGraph(*root, *loaded.root);
        expectSameBounds(root, loaded.root);
    }
}

TEST(Gltf, ComparisonNoticesAChangedGraph) {
    // The comparison the round trips rely on fails when something differs.
    ref_ptr<Group> a = allKindsScene(), b = allKindsScene();
    static_cast<Switch*>(findByName(*b, "switch"))->setOn(0, false);
    std::map<const Node*, const Node*> seen;
    std::string why;
    EXPECT_FALSE(sameGraph(*a, *b, seen, why));
    EXPECT_NE(why.find("switch"), std::string::npos) << why;
}

TEST(Gltf, SavingToAnUnwritablePathThrowsNamingIt) {
    auto root = allKindsScene();
    try {
        saveGltf(*root, "/nonexistent-dir/x.glb");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.glb"), std::string::npos) << e.what();
    }
}

// --- glTF features from hand-written files

TEST(Gltf, MeshUsedByTwoNodesBecomesOneGeometryWithTwoParents) {
    Doc d;
    d.json = R"("scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "translation": [1, 0, 0]}, {"mesh": 0, "rotation": [0, 0, 0.7071067811865476, 0.7071067811865476], "scale": [2, 2, 2]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}])";
    const GltfScene s = d.load();
    ASSERT_EQ(s.root->numChildren(), 2u);
    Node* g0 = s.root->child(0)->child(0);
    Node* g1 = s.root->child(1)->child(0);
    ASSERT_EQ(g0->kind(), NodeKind::Geometry);
    EXPECT_EQ(g0, g1);
    EXPECT_EQ(g0->numParents(), 2u);
    EXPECT_EQ(static_cast<Geometry*>(g0)->mesh()->triangleCount(), 1u);
    // TRS: translate * rotate * scale.
    const dmat4 m = static_cast<Transform*>(s.root->child(1))->matrix();
    const dvec4 x = m * dvec4(1, 0, 0, 1);
    EXPECT_NEAR(x.x, 0.0, 1e-12);
    EXPECT_NEAR(x.y, 2.0, 1e-12);
    EXPECT_EQ(static_cast<Transform*>(s.root->child(0))->translation(), dvec3(1, 0, 0));
}

TEST(Gltf, StripsAndFansBecomeTrianglesPointsAndLinesLoadAsThemselves) {
    Doc d;
    d.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    d.indices = {0, 1, 2, 3, 0, 0};
    d.json = R"("scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 5},
                                   {"attributes": {"POSITION": 0}, "mode": 6},
                                   {"attributes": {"POSITION": 0}, "mode": 0},
                                   {"attributes": {"POSITION": 0}, "mode": 1}]}])";
    const GltfScene s = d.load();
    Node* t = s.root->child(0);
    ASSERT_EQ(t->numChildren(), 4u);
    const Mesh* strip = static_cast<Geometry*>(t->child(0))->mesh();
    const Mesh* fan = static_cast<Geometry*>(t->child(1))->mesh();
    ASSERT_EQ(strip->triangleCount(), 2u);
    ASSERT_EQ(fan->triangleCount(), 2u);
    // Strip 0 1 2 3: (0 1 2) then (2 1 3), both wound like the first.
    EXPECT_EQ(strip->index(3), 2u);
    EXPECT_EQ(strip->index(4), 1u);
    EXPECT_EQ(strip->index(5), 3u);
    // Fan 0 1 2 3: (0 1 2), (0 2 3).
    EXPECT_EQ(fan->index(3), 0u);
    EXPECT_EQ(fan->index(4), 2u);
    EXPECT_EQ(fan->index(5), 3u);
    // Points: the four positions in order; lines: (0 1) and (2 3).
    const Mesh* points = static_cast<Geometry*>(t->child(2))->mesh();
    const Mesh* lines = static_cast<Geometry*>(t->child(3))->mesh();
    EXPECT_EQ(points->primitive(), Primitive::Points);
    EXPECT_EQ(points->pointCount(), 4u);
    EXPECT_EQ(points->indexCount(), 0u);
    ASSERT_EQ(lines->lineCount(), 2u);
    EXPECT_EQ(lines->index(2), 2u);
    EXPECT_EQ(lines->index(3), 3u);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
}

TEST(Gltf, CamerasCarryTheirNodesWorldMatrix) {
    Doc d;
    d.json = R"("scenes": [{"nodes": [0]}],
        "nodes": [{"translation": [0, 0, 10], "children": [1]}, {"camera": 0, "rotation": [0, 0.7071067811865476, 0, 0.7071067811865476], "name": "eye"}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1, "zfar": 100, "aspectRatio": 1.5}}])";
    const GltfScene s = d.load();
    ASSERT_EQ(s.cameras.size(), 1u);
    const GltfCamera& c = s.cameras[0];
    EXPECT_EQ(c.name, "eye");
    EXPECT_TRUE(c.perspective);
    EXPECT_NEAR(c.yfovDegrees, 0.5 * 180.0 / M_PI, 1e-9);
    EXPECT_EQ(c.aspect, 1.5);
    EXPECT_EQ(c.zfar, 100.0);
    const dvec3 eye(c.world * dvec4(0, 0, 0, 1));
    const dvec3 look(c.world * dvec4(0, 0, -1, 0));
    EXPECT_NEAR(glm::length(eye - dvec3(0, 0, 10)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(look - dvec3(-1, 0, 0)), 0.0, 1e-12);  // -Z turned a quarter about +Y
}

TEST(Gltf, ExternalBuffersAreReadBesideTheFileButNeverWhenLoadingFromMemory) {
    Doc d;
    d.externalBin = "sgkit_gltf_ext.bin";
    d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}])";
    const std::string text = d.text();
    writeFile(tempPath("ext.gltf"), text);
    const std::string bin = d.binary();
    writeFile(::testing::TempDir() + d.externalBin, bin);
    const GltfScene s = loadGltf(tempPath("ext.gltf"));
    ASSERT_EQ(s.root->numChildren(), 1u);
    EXPECT_EQ(static_cast<Geometry*>(s.root->child(0)->child(0))->mesh()->positions().size(), 3u);
    try {
        loadGltfFromMemory("mem.gltf", text.data(), text.size());
        FAIL() << "loaded an external buffer from memory";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), "mem.gltf");
        EXPECT_NE(e.reason().find("not read when loading from memory"), std::string::npos) << e.what();
    }
}

TEST(Gltf, BaseColourTextureIsLoaded) {
    auto root = make<Group>();
    std::vector<uint8_t> px;
    for (int i = 0; i < 4 * 3; ++i) px.insert(px.end(), {uint8_t(20 * i), uint8_t(255 - 20 * i), 7, 255});
    auto mat = make<Material>(vec4(0.5f, 0.25f, 1.0f, 1.0f), make<Texture>(4, 3, px));
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), mat));
    const GltfScene s = roundTrip(*root, ".glb");
    const Material* m = static_cast<Geometry*>(s.root->child(0))->material();
    ASSERT_TRUE(m && m->texture);
    EXPECT_EQ(m->baseColor, mat->baseColor);
    EXPECT_EQ(m->texture->width(), 4);
    EXPECT_EQ(m->texture->rgba(), px);
}

TEST(Gltf, MaskedMaterialsCarryTheirAlphaCutoff) {
    // MASK with and without a cutoff (glTF's default is 0.5); OPAQUE and BLEND ignore alphaCutoff.
    Doc d;
    d.json = R"("scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [{"mesh": 0}, {"mesh": 1}, {"mesh": 2}, {"mesh": 3}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
                   {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]},
                   {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 2}]},
                   {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 3}]}],
        "materials": [{"alphaMode": "MASK", "alphaCutoff": 0.25}, {"alphaMode": "MASK"},
                      {"alphaCutoff": 0.75}, {"alphaMode": "BLEND", "alphaCutoff": 0.75}])";
    const GltfScene s = d.load();
    ASSERT_EQ(s.root->numChildren(), 4u);
    auto cutoff = [&](size_t i) {
        const Node* g = s.root->child(i);
        while (g->kind() != NodeKind::Geometry) g = static_cast<const Group*>(g)->child(0);
        const Material* m = static_cast<const Geometry*>(g)->material();
        return m ? m->alphaCutoff : -1.0f;
    };
    EXPECT_EQ(cutoff(0), 0.25f);
    EXPECT_EQ(cutoff(1), 0.5f);
    EXPECT_EQ(cutoff(2), 0.0f);
    EXPECT_EQ(cutoff(3), 0.0f);

    // Written back as MASK with the cutoff (also when it is glTF's default), and not at all when off.
    auto root = make<Group>();
    auto box = makeBoxMesh(dvec3(-1), dvec3(1));
    for (float c : {0.0f, 0.5f, 0.3f}) {
        auto mat = make<Material>();
        mat->alphaCutoff = c;
        root->addChild(make<Geometry>(box, mat));
    }
    const GltfScene back = roundTrip(*root, ".gltf");
    ASSERT_EQ(back.root->numChildren(), 3u);
    for (size_t i = 0; i < 3; ++i)
        EXPECT_EQ(static_cast<Geometry*>(back.root->child(i))->material()->alphaCutoff,
                  static_cast<Geometry*>(root->child(i))->material()->alphaCutoff)
            << i;
}

// --- malformed files: one per error class, each with its JSON path and reason

struct BadCase {
    const char* what;
    std::function<void(Doc&)> edit;
    std::string path, reason;
};

TEST(Gltf, MalformedFilesNameFilePathAndReason) {
    const std::string mesh = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}])";
    const std::vector<BadCase> cases = {
        {"accessor past its buffer view",
         [&](Doc& d) {
             d.json = mesh;
             d.positionCount = 4;
         },
         "accessors[0]", "is past the end of bufferViews[0]"},
        {"buffer view past its buffer",
         [&](Doc& d) {
             d.json = mesh;
             d.viewExtra = 16;
         },
         "bufferViews[0]", "is past the end of buffer 0"},
        {"index out of range",
         [&](Doc& d) {
             d.json = mesh;
             d.indices = {0, 1, 7};
         },
         "meshes[0].primitives[0].indices", "index 7 at element 2 is out of range (3 vertices)"},
        {"attribute counts differ",
         [&](Doc& d) {
             d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 2}, "indices": 1}]}])";
             d.extraAccessors = R"(, {"bufferView": 0, "componentType": 5126, "count": 2, "type": "VEC3"})";
         },
         "meshes[0].primitives[0].attributes.NORMAL", "count 2 differs from POSITION's count 3"},
        {"stride smaller than the element",
         [&](Doc& d) {
             d.json = mesh;
             d.positionStride = 8;
         },
         "accessors[0]", "element of 12 bytes is larger than bufferViews[0].byteStride 8"},
        {"NaN position",
         [&](Doc& d) {
             d.json = mesh;
             d.positions[1].y = std::nanf("");
         },
         "meshes[0].primitives[0].attributes.POSITION", "element 1 is not finite"},
        {"infinite position",
         [&](Doc& d) {
             d.json = mesh;
             d.positions[2].z = INFINITY;
         },
         "meshes[0].primitives[0].attributes.POSITION", "element 2 is not finite"},
        // JSON cannot spell infinity (the parser rejects 1e999, see below); matrices overflow when composed.
        {"world matrix overflows",
         [&](Doc& d) {
             d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"translation": [1e308, 0, 0], "children": [1]},
                 {"translation": [1e308, 0, 0]}])";
         },
         "nodes[1].translation", "world matrix is not finite (element [3][0] is inf)"},
        {"cycle",
         [&](Doc& d) { d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{}, {"children": [2]}, {"children": [1]}])"; },
         "nodes[2].children[0]", "the node hierarchy has a cycle: nodes[1] -> nodes[2] -> nodes[1]"},
        {"node its own child", [&](Doc& d) { d.json = R"("nodes": [{"children": [0]}])"; }, "nodes[0].children[0]",
         "is its own child"},
        {"two parents",
         [&](Doc& d) {
             d.json = R"("scenes": [{"nodes": [0, 1]}], "nodes": [{"children": [2]}, {"children": [2]}, {}])";
         },
         "nodes[1].children[0]", "node 2 has two parents: nodes[0] and nodes[1]"},
        {"scene lists a child node",
         [&](Doc& d) { d.json = R"("scenes": [{"nodes": [0, 1]}], "nodes": [{"children": [1]}, {}])"; },
         "scenes[0].nodes[1]", "node 1 is not a root node"},
        {"unsupported required extension",
         [&](Doc& d) {
             d.json = mesh +
                      R"(, "extensionsUsed": ["EXT_made_up_geometry"], "extensionsRequired": ["EXT_made_up_geometry"])";
         },
         "extensionsRequired[0]", "extension 'EXT_made_up_geometry' is required but not supported"},
        {"missing mesh", [&](Doc& d) { d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 3}])"; },
         "nodes[0].mesh", "mesh 3 does not exist (0 meshes)"},
        {"missing child", [&](Doc& d) { d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"children": [5]}])"; },
         "nodes[0].children[0]", "node 5 does not exist (1 node)"},
        {"missing accessor",
         [&](Doc& d) {
             d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                 "meshes": [{"primitives": [{"attributes": {"POSITION": 9}}]}])";
         },
         "meshes[0].primitives[0].attributes.POSITION", "accessor 9 does not exist (2 accessors)"},
        {"wrong attribute type",
         [&](Doc& d) {
             d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                 "meshes": [{"primitives": [{"attributes": {"POSITION": 1}}]}])";
         },
         "meshes[0].primitives[0].attributes.POSITION", "needs VEC3 of componentType 5126"},
        {"bad sgkit extras",
         [&](Doc& d) {
             d.json =
                 R"("scenes": [{"nodes": [0]}], "nodes": [{"extras": {"sgkit": {"kind": "LOD", "ranges": [[5, 1]]}}, "children": [1]}, {}])";
         },
         "nodes[0].children[0]", "has min > max"},
        {"sgkit extras out of float range",
         [&](Doc& d) {
             d.json =
                 R"("scenes": [{"nodes": [0]}], "nodes": [{"extras": {"sgkit": {"kind": "LOD", "ranges": [[0, 1e300]]}}, "children": [1]}, {}])";
         },
         "nodes[0].extras.sgkit.ranges[0]", "is out of float range"},
        {"colour out of float range",
         [&](Doc& d) {
             d.json = mesh + R"(, "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1e300, 1, 1]}}])";
         },
         "materials[0].pbrMetallicRoughness.baseColorFactor", "element 1 is out of float range"},
        {"huge accessor without data",
         [&](Doc& d) {
             d.json = mesh;
             d.extraAccessors = R"(, {"componentType": 5126, "count": 100000000000, "type": "VEC3"})";
         },
         "accessors[2].count", "without a bufferView is above"},
        {"integer with a fraction",
         [&](Doc& d) {
             d.json = mesh;
             d.extraAccessors = R"(, {"bufferView": 0, "componentType": 5126, "count": 1.5, "type": "VEC3"})";
         },
         "accessors[2].count", "must be an integer, not 1.5"},
        {"unknown sgkit kind",
         [&](Doc& d) {
             d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"extras": {"sgkit": {"kind": "Teapot"}}}])";
         },
         "nodes[0].extras.sgkit.kind", "unknown node kind 'Teapot'"},
        {"JSON nested too deep",
         [&](Doc& d) {
             d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"extras": )" + std::string(100, '[') +
                      std::string(100, ']') + "}]";
         },
         "", "JSON nested deeper than 64 levels"},
    };
    for (const BadCase& c : cases) {
        for (bool glb : {false, true}) {
            SCOPED_TRACE(std::string(c.what) + (glb ? " (.glb)" : " (.gltf)"));
            Doc d;
            c.edit(d);
            const std::string name = glb ? "bad.glb" : "bad.gltf";
            const std::string bytes = glb ? d.glb() : d.text();
            try {
                loadGltfFromMemory(name, bytes.data(), bytes.size());
                ADD_FAILURE() << "loaded";
            } catch (const LoadError& e) {
                EXPECT_EQ(e.file(), name);
                EXPECT_EQ(e.jsonPath(), c.path) << e.what();
                EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.what();
                EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
            }
        }
    }
}

TEST(Gltf, MalformedGlbContainersAreRejectedBeforeParsing) {
    Doc d;
    d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}])";
    const std::string good = d.glb();
    ASSERT_NO_THROW(loadGltfFromMemory("good.glb", good.data(), good.size()));
    auto expectError = [](std::string bytes, const std::string& reason) {
        try {
            loadGltfFromMemory("c.glb", bytes.data(), bytes.size());
            ADD_FAILURE() << "loaded: " << reason;
        } catch (const LoadError& e) {
            EXPECT_EQ(e.jsonPath(), "");
            EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
        }
    };
    const uint32_t jsonLen = le32(good, 12);
    std::string binTooLong = good;  // the BIN chunk claims 8 bytes more than the file holds
    setLe32(binTooLong, 20 + jsonLen, le32(good, 20 + jsonLen) + 8);
    expectError(binTooLong, "BIN chunk of");
    expectError(good.substr(0, good.size() - 4), "GLB header claims");
    std::string wrongVersion = good;
    setLe32(wrongVersion, 4, 1);
    expectError(wrongVersion, "GLB version 1");
    expectError(good.substr(0, 12), "shorter than its 20-byte header");
}

TEST(Gltf, ErrorsFoundByTinygltfCarryItsMessage) {
    // tinygltf rejects some files itself (JSON syntax, numbers that overflow, some index checks); its
    // messages name no JSON path.
    Doc d;
    d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"translation": [0, -1e400, 0]}])";
    const std::string t = d.text();
    try {
        loadGltfFromMemory("overflow.gltf", t.data(), t.size());
        FAIL() << "loaded";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), "overflow.gltf");
        EXPECT_NE(e.reason().find("overflow"), std::string::npos) << e.what();
    }
}

TEST(Gltf, MissingFileNamesItself) {
    try {
        loadGltf(tempPath("does-not-exist.glb"));
        FAIL() << "loaded";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), tempPath("does-not-exist.glb"));
        EXPECT_NE(e.reason().find("cannot open"), std::string::npos) << e.what();
    }
}

TEST(Gltf, SharedNodesThatExpandToAHugeSceneAreRefused) {
    // Group k holds group k-1 twice (once written out, once by its id): 2^(k+1) - 1 nodes per path.
    auto layered = [](int layers) {
        std::string nodes = R"({"extras": {"sgkit": {"kind": "Group", "id": 0}}})";
        for (int k = 1; k <= layers; ++k) {
            nodes += R"(, {"extras": {"sgkit": {"kind": "Group", "id": )" + std::to_string(k - 1) + "}}}";
            nodes += R"(, {"extras": {"sgkit": {"kind": "Group", "id": )" + std::to_string(k) + R"(}}, "children": [)" +
                     std::to_string(2 * k - 2) + ", " + std::to_string(2 * k - 1) + "]}";
        }
        return R"("scenes": [{"nodes": [)" + std::to_string(2 * layers) + R"(]}], "nodes": [)" + nodes + "]";
    };
    Doc d;
    d.json = layered(30);
    try {
        d.load();
        FAIL() << "loaded";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath(), "nodes[52]") << e.what();  // group 26: 2^27 - 1 nodes
        EXPECT_NE(e.reason().find("expands to more than"), std::string::npos) << e.what();
    }
    // Twenty layers (about a million entries) load, sharing their nodes.
    d.json = layered(20);
    const GltfScene s = d.load();
    EXPECT_EQ(s.root->child(0)->child(0)->child(0), s.root->child(0)->child(1)->child(0));
}

TEST(Gltf, DirectoriesAndPipesAreRefusedWithoutWaiting) {
    const std::string fifo = tempPath("pipe.glb");
    std::remove(fifo.c_str());
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    for (const std::string& path : {fifo, ::testing::TempDir()}) {
        try {
            loadGltf(path);
            ADD_FAILURE() << "loaded " << path;
        } catch (const LoadError& e) {
            EXPECT_NE(e.reason().find("not a regular file"), std::string::npos) << e.what();
        }
    }
    std::remove(fifo.c_str());
}

// Corrupted copies of valid files (bytes flipped, runs overwritten, cut short): each loads or throws
// LoadError; nothing else may escape, and under the sanitizers nothing may crash or leak.
TEST(Gltf, RandomCorruptionLoadsOrThrowsLoadError) {
    ref_ptr<Group> root = scenes::buildRandomScene(7, {6, 10.0, dvec3(0.0)});
    std::vector<std::string> files;
    for (const char* ext : {".glb", ".gltf"}) {
        saveGltf(*root, tempPath(std::string("corrupt") + ext));
        const auto b = readFile(tempPath(std::string("corrupt") + ext));
        files.emplace_back(b.begin(), b.end());
    }
    std::mt19937_64 rng(12345);
    int loaded = 0, rejected = 0;
    for (int round = 0; round < 1500; ++round) {
        std::string bytes = files[size_t(round % 2)];
        const bool glb = round % 2 == 0;
        switch (rng() % 4) {
            case 0:  // flip a few bits anywhere
                for (int k = 0, n = 1 + int(rng() % 8); k < n; ++k)
                    bytes[rng() % bytes.size()] ^= char(1u << (rng() % 8));
                break;
            case 1: {  // overwrite a digit, quote or bracket in the JSON
                const std::string pick = "0123456789\"[]{},:-e.";
                for (int k = 0, n = 1 + int(rng() % 4); k < n; ++k) {
                    const size_t at =
                        glb ? 20 + rng() % std::min<size_t>(bytes.size() - 20, le32(bytes, 12)) : rng() % bytes.size();
                    bytes[at] = pick[rng() % pick.size()];
                }
                break;
            }
            case 2: bytes.resize(rng() % bytes.size()); break;  // cut short
            default: {                                          // a run of random bytes
                const size_t at = rng() % bytes.size(), n = std::min<size_t>(bytes.size() - at, 1 + rng() % 64);
                for (size_t k = 0; k < n; ++k) bytes[at + k] = char(rng());
            }
        }
        try {
            loadGltfFromMemory(glb ? "c.glb" : "c.gltf", bytes.data(), bytes.size());
            ++loaded;
        } catch (const LoadError& e) {
            ++rejected;
            EXPECT_FALSE(e.reason().empty());
        }
    }
    EXPECT_GT(rejected, 100);
    EXPECT_GT(loaded, 10);  // flips inside vertex data and names load
}

TEST(Gltf, ProgressIsReportedInOrderUpToDone) {
    ref_ptr<Group> root = scenes::buildRandomScene(3);
    saveGltf(*root, tempPath("progress.glb"));
    std::vector<std::pair<double, std::string>> seen;
    GltfLoadOptions opt;
    opt.progressAfterSeconds = 0.0;
    opt.progress = [&](double f, const std::string& stage) { seen.emplace_back(f, stage); };
    loadGltf(tempPath("progress.glb"), opt);
    ASSERT_GE(seen.size(), 2u);
    EXPECT_LT(seen.front().first, 1.0);
    for (size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i].first, seen[i - 1].first) << seen[i].second;
    EXPECT_EQ(seen.back().first, 1.0);
    EXPECT_EQ(seen.back().second, "done");
    // The default waits a second: a small load reports nothing.
    size_t quiet = 0;
    GltfLoadOptions def;
    def.progress = [&](double, const std::string&) { ++quiet; };
    loadGltf(tempPath("progress.glb"), def);
    EXPECT_EQ(quiet, 0u);
}

TEST(Gltf, ApplicationPropertiesTravelInExtrasBesideSgkitsOwn) {
    auto root = make<Group>();
    auto lod = make<LOD>();
    lod->addChild(make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1)), make<Material>()), 0.0f, 100.0f);
    auto plain = make<Transform>(glm::translate(dmat4(1.0), dvec3(1, 2, 3)));
    root->addChild(lod);
    root->addChild(plain);
    GltfSaveOptions o;
    o.nodeProperties = [&](const Node& n) {
        GltfProperties p;
        if (&n == lod.get()) {
            p.strings["id"] = "48201";
            p.numbers["area"] = 4602.5;
            p.strings["sgkit"] = "ignored: the key is sgkit's";
        }
        return p;
    };
    o.sceneProperties.strings["level"] = "state";
    for (const char* ext : {".glb", ".gltf"}) {
        const std::string path = tempPath(std::string("properties") + ext);
        saveGltf(*root, path, o);
        const GltfScene s = loadGltf(path);
        ASSERT_EQ(s.root->numChildren(), 2u);
        const Node* l = s.root->child(0);
        EXPECT_EQ(l->kind(), NodeKind::LOD) << "sgkit's extras still read";
        ASSERT_EQ(s.properties.count(l), 1u);
        EXPECT_EQ(s.properties.at(l).strings.at("id"), "48201");
        EXPECT_EQ(s.properties.at(l).numbers.at("area"), 4602.5);
        EXPECT_EQ(s.properties.at(l).strings.count("sgkit"), 0u);
        EXPECT_EQ(s.properties.count(s.root->child(1)), 0u) << "a node without properties has none";
        EXPECT_EQ(s.sceneProperties.strings.at("level"), "state");
    }
    // Without options, nothing but sgkit's own keys is written.
    saveGltf(*root, tempPath("noproperties.glb"));
    const GltfScene s = loadGltf(tempPath("noproperties.glb"));
    EXPECT_TRUE(s.properties.empty());
    EXPECT_TRUE(s.sceneProperties.empty());
}

TEST(Gltf, PagedNodesKeepTheirFileRangeAndTriggerButNotTheirDetail) {
    auto root = make<Group>();
    auto p = make<PagedLOD>();
    p->setName("tile");
    p->setFile("tiles/a.glb");
    p->setMode(PagedLOD::Mode::PixelSize);
    p->setRange(200.0f, 1e9f);
    p->setCenter(dvec3(1, 2, 3));
    p->setRadius(7.5);
    p->setTrigger(PagedLOD::Trigger::Command);
    p->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
    p->attachDetail(make<Group>(), 0);
    root->addChild(p);
    const std::string path = tempPath("paged.gltf");
    saveGltf(*root, path);
    const GltfScene s = loadGltf(path);
    ASSERT_EQ(s.root->numChildren(), 1u);
    ASSERT_EQ(s.root->child(0)->kind(), NodeKind::PagedLOD);
    const auto* q = static_cast<const PagedLOD*>(s.root->child(0));
    EXPECT_EQ(q->name(), "tile");
    // Relative to the directory of the file that names it.
    EXPECT_EQ(q->file(), ::testing::TempDir() + "tiles/a.glb");
    EXPECT_EQ(q->mode(), PagedLOD::Mode::PixelSize);
    EXPECT_EQ(q->rangeMin(), 200.0f);
    EXPECT_EQ(q->rangeMax(), 1e9f);
    EXPECT_EQ(q->center(), dvec3(1, 2, 3));
    EXPECT_EQ(q->radius(), 7.5);
    EXPECT_EQ(q->trigger(), PagedLOD::Trigger::Command);
    EXPECT_EQ(q->state(), PagedLOD::State::Unloaded);
    ASSERT_EQ(q->numChildren(), 1u);  // the coarse level; the detail stays in its own file
    EXPECT_EQ(q->child(0)->kind(), NodeKind::Geometry);
    EXPECT_EQ(q->detail(), nullptr);
    std::remove(path.c_str());
}
