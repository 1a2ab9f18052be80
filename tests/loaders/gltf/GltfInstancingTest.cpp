// EXT_mesh_gpu_instancing: hand-written files read to the expected Instances, bad instancing refused with its
// JSON path, Instances written as instanced nodes and read back, the written file checked by Khronos' validator,
// and gltfpack's instanced output read.
#include "GltfTestUtil.h"
#include "OutsideTools.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <random>
#include <tuple>

using namespace sg;
using namespace gltftest;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kAttrs = "nodes[0].extensions.EXT_mesh_gpu_instancing.attributes";

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_gltfinst_" + name; }

template <class T>
std::string bytesOf(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// An accessor into bufferViews[2] (Doc::extraBytes), with the comma that appends it to Doc's two.
std::string accessor(size_t offset, int comp, size_t count, const char* type, bool normalized = false) {
    return ", {\"bufferView\": 2, \"byteOffset\": " + std::to_string(offset) +
           ", \"componentType\": " + std::to_string(comp) + ", \"count\": " + std::to_string(count) + ", \"type\": \"" +
           type + "\"" + (normalized ? ", \"normalized\": true" : "") + "}";
}

// Three instances: a translation, a quarter turn about y with scale 2, a half turn about x with scale (1, 3, 1).
struct Trs {
    std::vector<float> t{1, 2, 3, 0, 0, -5, 4, 0, 0};
    std::vector<float> r{0, 0, 0, 1, 0, float(std::sqrt(0.5)), 0, float(std::sqrt(0.5)), 1, 0, 0, 0};
    std::vector<float> s{1, 1, 1, 2, 2, 2, 1, 3, 1};
};

// Node 0 holds mesh 0 and the instancing extension (accessors 2, 3, 4: TRANSLATION, ROTATION, SCALE).
Doc instancedDoc(const Trs& d, const std::string& node = "",
                 const std::string& attributes = R"({"TRANSLATION": 2, "ROTATION": 3, "SCALE": 4})") {
    Doc doc;
    doc.extraBytes = bytesOf(d.t) + bytesOf(d.r) + bytesOf(d.s);
    doc.extraAccessors = accessor(0, 5126, d.t.size() / 3, "VEC3") +
                         accessor(4 * d.t.size(), 5126, d.r.size() / 4, "VEC4") +
                         accessor(4 * (d.t.size() + d.r.size()), 5126, d.s.size() / 3, "VEC3");
    doc.json =
        R"("scenes": [{"nodes": [0]}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0)" +
        node + R"(, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": )" + attributes + "}}}]";
    return doc;
}

dmat4 trs(const dvec3& t, const glm::dquat& q, const dvec3& s) {
    return glm::scale(glm::translate(dmat4(1.0), t) * glm::mat4_cast(q / glm::length(q)), s);
}

void expectNear(const dmat4& a, const dmat4& b, double tol, const std::string& what) {
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(a[c][k], b[c][k], tol) << what << " [" << c << "][" << k << "]";
}

// Every Geometry drawn below root, as (world matrix, vertex count), sorted by where it is.
std::vector<std::pair<dmat4, size_t>> draws(const Node& root) {
    std::vector<std::pair<dmat4, size_t>> out;
    std::function<void(const Node&, const dmat4&)> walk = [&](const Node& n, const dmat4& world) {
        dmat4 w = world;
        if (n.kind() == NodeKind::Transform) w = world * static_cast<const Transform&>(n).matrix();
        if (n.kind() == NodeKind::Instance) w = world * static_cast<const Instance&>(n).matrix();
        if (n.kind() == NodeKind::Geometry) {
            const Mesh* m = static_cast<const Geometry&>(n).mesh();
            out.push_back({w, m ? m->positions().size() : 0});
        }
        for (size_t i = 0; i < n.numChildren(); ++i) walk(*n.child(i), w);
    };
    walk(root, dmat4(1.0));
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
        return std::make_tuple(a.first[3].x, a.first[3].y, a.first[3].z) <
               std::make_tuple(b.first[3].x, b.first[3].y, b.first[3].z);
    });
    return out;
}

size_t countKind(const Node& n, NodeKind k) {
    size_t c = n.kind() == k;
    for (size_t i = 0; i < n.numChildren(); ++i) c += countKind(*n.child(i), k);
    return c;
}

Box worldBox(const ref_ptr<Node>& root) {
    Scene s(root);
    s.update();
    return s.image().box(0);
}

// Instances of every sort the writer meets: batched under a Transform (on its own node), under a Group and at
// the scene's root (through a Transform prototype, folded); not batched: a shear, a named one, under an LOD.
ref_ptr<Group> instancedScene(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto randomTrs = [&](double spread) {
        const glm::dquat q(u(rng), u(rng), u(rng), u(rng));
        return trs(dvec3(u(rng), u(rng), u(rng)) * spread, q, dvec3(1.25 + u(rng), 1.25 + u(rng), 1.25 + u(rng)));
    };
    auto box = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>(vec4(0.8f, 0.3f, 0.2f, 1.0f)));
    auto slab = make<Geometry>(makeBoxMesh(dvec3(-2, -0.2, -1), dvec3(2, 0.2, 1)), make<Material>());
    auto root = make<Group>();
    auto place = make<Transform>(glm::rotate(glm::translate(dmat4(1.0), dvec3(5, 0, -3)), 0.3, dvec3(0, 1, 0)));
    for (int i = 0; i < 6; ++i) place->addChild(make<Instance>(box, randomTrs(20.0)));
    dmat4 shear(1.0);
    shear[1][0] = 0.5;
    shear[3] = dvec4(0, 40, 0, 1);
    place->addChild(make<Instance>(box, shear));
    place->addChild(slab);
    place->setName("place");
    root->addChild(place);

    auto folded = make<Transform>(glm::scale(glm::translate(dmat4(1.0), dvec3(0, 1, 0)), dvec3(0.5)));
    folded->addChild(slab);
    for (int i = 0; i < 4; ++i) root->addChild(make<Instance>(folded, randomTrs(30.0)));

    auto group = make<Group>();
    for (int i = 0; i < 3; ++i) group->addChild(make<Instance>(slab, randomTrs(25.0)));
    root->addChild(group);

    auto lod = make<LOD>();
    lod->addChild(make<Instance>(box, randomTrs(10.0)), 0.0f, 50.0f);
    lod->addChild(make<Instance>(box, randomTrs(10.0)), 50.0f, 1e5f);
    root->addChild(lod);
    auto named = make<Instance>(box, randomTrs(10.0));
    named->setName("named");
    root->addChild(named);
    root->addChild(make<Instance>(box, randomTrs(10.0)));  // the root's one Instance of `box`: written as it is
    return root;
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(GltfInstancing, HandWrittenInstancesBecomeInstancesOfTheMeshInsideTheNode) {
    Doc doc = instancedDoc(Trs{}, R"(, "translation": [10, 0, 0], "children": [1])");
    doc.json.replace(doc.json.rfind("]"), 1, R"(, {"mesh": 0, "translation": [0, 7, 0]}])");
    doc.json += R"(, "extensionsUsed": ["EXT_mesh_gpu_instancing"], "extensionsRequired": ["EXT_mesh_gpu_instancing"])";
    const GltfScene s = doc.load();
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    ASSERT_EQ(s.root->numChildren(), 1u);
    const auto& node = static_cast<const Transform&>(*s.root->child(0));
    ASSERT_EQ(node.kind(), NodeKind::Transform);
    EXPECT_EQ(node.matrix(), glm::translate(dmat4(1.0), dvec3(10, 0, 0)));
    ASSERT_EQ(node.numChildren(), 4u);  // three instances, then the node's own child (not instanced)
    const double h = std::sqrt(0.5);
    const dmat4 expected[3] = {trs(dvec3(1, 2, 3), glm::dquat(1, 0, 0, 0), dvec3(1)),
                               trs(dvec3(0, 0, -5), glm::dquat(float(h), 0, float(h), 0), dvec3(2)),
                               trs(dvec3(4, 0, 0), glm::dquat(0, 1, 0, 0), dvec3(1, 3, 1))};
    for (size_t i = 0; i < 3; ++i) {
        ASSERT_EQ(node.child(i)->kind(), NodeKind::Instance);
        const auto& in = static_cast<const Instance&>(*node.child(i));
        expectNear(in.matrix(), expected[i], 1e-12, "instance " + std::to_string(i));
        EXPECT_EQ(in.prototype(), static_cast<const Instance&>(*node.child(0)).prototype());
        EXPECT_EQ(in.prototype()->kind(), NodeKind::Geometry);
    }
    EXPECT_EQ(node.child(3)->kind(), NodeKind::Transform);
    // The quarter turn about y takes the triangle's x edge to -z, scaled by 2: world = node * instance.
    const dvec4 p = node.matrix() * static_cast<const Instance&>(*node.child(1)).matrix() * dvec4(1, 0, 0, 1);
    EXPECT_NEAR(glm::length(dvec3(p) - dvec3(10, 0, -7)), 0.0, 1e-6);
    Box want = transformBox(glm::translate(dmat4(1.0), dvec3(10, 7, 0)), Box{dvec3(0), dvec3(1, 1, 0)});
    for (const dmat4& m : expected) want.expand(transformBox(node.matrix() * m, Box{dvec3(0), dvec3(1, 1, 0)}));
    const Box got = worldBox(s.root);  // (the image's boxes are rounded outward to float)
    EXPECT_NEAR(glm::length(got.min - want.min), 0.0, 1e-5);
    EXPECT_NEAR(glm::length(got.max - want.max), 0.0, 1e-5);
}

TEST(GltfInstancing, NormalizedIntegerRotationsAndMissingAttributesAreRead) {
    for (int comp : {5120, 5122}) {
        SCOPED_TRACE(comp);
        Doc doc;
        if (comp == 5120)
            doc.extraBytes = bytesOf(std::vector<int8_t>{0, 127, 0, 127, 0, 0, 0, -128});
        else
            doc.extraBytes = bytesOf(std::vector<int16_t>{0, 32767, 0, 32767, 0, 0, 0, -32768});
        doc.extraAccessors = accessor(0, comp, 2, "VEC4", true);
        doc.json =
            R"("scenes": [{"nodes": [0]}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
            "nodes": [{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"ROTATION": 2, "_ID": 2}}}}])";
        const GltfScene s = doc.load();
        const Node& node = *s.root->child(0);
        ASSERT_EQ(node.numChildren(), 2u);
        const double h = std::sqrt(0.5);
        expectNear(static_cast<const Instance&>(*node.child(0)).matrix(),
                   trs(dvec3(0), glm::dquat(h, 0, h, 0), dvec3(1)), 1e-12, "quarter turn");
        expectNear(static_cast<const Instance&>(*node.child(1)).matrix(), dmat4(1.0), 1e-12, "w = -1: no turn");
    }
}

TEST(GltfInstancing, AMeshOfSeveralPrimitivesIsOnePrototypeForEveryInstance) {
    Doc doc = instancedDoc(Trs{});
    const std::string one = R"("indices": 1}]}])";
    doc.json.replace(doc.json.find(one), one.size(),
                     R"("indices": 1, "material": 0}, {"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]}],
                        "materials": [{}, {}])");
    const GltfScene s = doc.load();
    const Node& node = *s.root->child(0);
    ASSERT_EQ(node.numChildren(), 3u);
    const Node* proto = static_cast<const Instance&>(*node.child(0)).prototype();
    ASSERT_EQ(proto->kind(), NodeKind::Group);
    EXPECT_EQ(proto->numChildren(), 2u);
    for (size_t i = 1; i < 3; ++i) EXPECT_EQ(static_cast<const Instance&>(*node.child(i)).prototype(), proto);
}

TEST(GltfInstancing, BadInstancingIsRefusedNamingItsPath) {
    struct Bad {
        const char* what;
        std::function<Doc()> doc;
        std::string path, reason;
    };
    auto with = [](std::function<void(Trs&)> f, const std::string& node = "") {
        return [f, node] {
            Trs d;
            f(d);
            return instancedDoc(d, node);
        };
    };
    auto attrs = [](const std::string& a, const std::string& extra = "") {
        return [a, extra] {
            Doc d = instancedDoc(Trs{}, "", a);
            d.extraAccessors += extra;
            return d;
        };
    };
    const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
    const std::vector<Bad> cases = {
        {"counts differ", with([](Trs& d) { d.s.resize(6); }), kAttrs + ".SCALE",
         "count 2 differs from ROTATION's count 3"},
        {"translation of VEC4",
         [] {
             Doc d = instancedDoc(Trs{});
             d.extraAccessors.replace(d.extraAccessors.find("VEC3"), 4, "VEC4");
             return d;
         },
         kAttrs + ".TRANSLATION", "accessor 2 is VEC4 of componentType 5126, needs VEC3"},
        {"scale of unsigned shorts", attrs(R"({"SCALE": 5})", accessor(0, 5123, 3, "VEC3")), kAttrs + ".SCALE",
         "needs VEC3 of componentType 5126"},
        {"rotation of bytes not normalized", attrs(R"({"ROTATION": 5})", accessor(0, 5120, 3, "VEC4")),
         kAttrs + ".ROTATION", "accessor 5 of componentType 5120 must be normalized"},
        {"accessor out of range", attrs(R"({"TRANSLATION": 99})"), kAttrs + ".TRANSLATION",
         "accessor 99 does not exist (5 accessors)"},
        {"not an index", attrs(R"({"TRANSLATION": "two"})"), kAttrs + ".TRANSLATION", "must be an accessor index"},
        {"no attributes", attrs("{}"), kAttrs, "must be an object naming at least one accessor"},
        {"NaN translation", with([&](Trs& d) { d.t[4] = nan; }), kAttrs + ".TRANSLATION", "instance 1 ("},
        {"infinite scale", with([&](Trs& d) { d.s[8] = inf; }), kAttrs + ".SCALE",
         "instance 2 (1.000000, 3.000000, inf"},
        {"zero quaternion", with([](Trs& d) { std::fill(d.r.begin() + 4, d.r.begin() + 8, 0.0f); }),
         kAttrs + ".ROTATION", "instance 1 is a quaternion of zero length"},
        {"singular scale", with([](Trs& d) { d.s[6] = 0.0f; }), kAttrs + ".SCALE", "instance 2 cannot be placed ("},
        {"too many instances",
         attrs(R"({"TRANSLATION": 5})", R"(, {"componentType": 5126, "count": 2097153, "type": "VEC3"})"), kAttrs,
         "2097153 instances are more than 2097152"},
        {"world matrix overflows",  // each node's scale 1e100 is fine, the world's 1e300 times 3e38 is not
         [] {
             Trs t;
             t.t[0] = 3e38f;
             Doc d = instancedDoc(t, R"(, "scale": [1e100, 1e100, 1e100])");
             d.json.replace(d.json.find(R"("nodes": [0])"), 12, R"("nodes": [1])");
             d.json.replace(d.json.rfind("]"), 1, R"(, {"scale": [1e100, 1e100, 1e100], "children": [2]},
                 {"scale": [1e100, 1e100, 1e100], "children": [0]}])");
             return d;
         },
         kAttrs, "instance 0's world matrix is not finite"},
    };
    for (const Bad& c : cases) {
        SCOPED_TRACE(c.what);
        const Doc d = c.doc();
        try {
            d.load();
            ADD_FAILURE() << "loaded";
        } catch (const LoadError& e) {
            EXPECT_EQ(e.file(), "doc.gltf");
            EXPECT_EQ(e.jsonPath(), c.path) << e.what();
            EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.what();
        }
    }
}

TEST(GltfInstancing, WithoutAMeshTheExtensionIsIgnoredWithAWarning) {
    Doc d = instancedDoc(Trs{}, "", R"({"TRANSLATION": 99})");
    d.json.replace(d.json.find(R"({"mesh": 0)"), 10, R"({"translation": [1, 0, 0])");
    const GltfScene s = d.load();
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_EQ(s.warnings[0], "nodes[0].extensions.EXT_mesh_gpu_instancing: needs a mesh to instance, ignored");
    EXPECT_EQ(countKind(*s.root, NodeKind::Instance), 0u);
}

TEST(GltfInstancing, InstancesSurviveARoundTripAsFewerNodes) {
    for (const char* ext : {".gltf", ".glb"}) {
        SCOPED_TRACE(ext);
        const ref_ptr<Group> root = instancedScene(7);
        const std::string path = tempPath(std::string("roundtrip") + ext);
        saveGltf(*root, path);
        const GltfScene loaded = loadGltf(path);
        EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
        const Box a = worldBox(root), b = worldBox(loaded.root);
        const double extent = glm::length(a.max - a.min);
        EXPECT_LT(glm::length(a.min - b.min), 1e-6 * extent);
        EXPECT_LT(glm::length(a.max - b.max), 1e-6 * extent);
        const auto da = draws(*root), db = draws(*loaded.root);
        ASSERT_EQ(da.size(), db.size());
        for (size_t i = 0; i < da.size(); ++i) {
            EXPECT_EQ(da[i].second, db[i].second) << "draw " << i;
            expectNear(da[i].first, db[i].first, 1e-5, "draw " + std::to_string(i));
        }
        // The Transform's six instances stay its first children, in order; the shear stays an Instance.
        const Node* found = findByName(*loaded.root, "place");
        ASSERT_TRUE(found && found->kind() == NodeKind::Transform);
        const Node& place = *found;
        ASSERT_EQ(place.numChildren(), 8u);
        for (size_t i = 0; i < 6; ++i) {
            const auto& want = static_cast<const Instance&>(*root->child(0)->child(i));
            const auto& got = static_cast<const Instance&>(*place.child(i));
            ASSERT_EQ(got.kind(), NodeKind::Instance);
            expectNear(got.matrix(), want.matrix(), 1e-5, "instance " + std::to_string(i));
        }
        EXPECT_EQ(countKind(*loaded.root, NodeKind::Instance), countKind(*root, NodeKind::Instance));
        if (std::string(ext) == ".gltf") {
            const json doc = json::parse(readText(path));
            EXPECT_LT(doc["nodes"].size(), countKind(*root, NodeKind::Instance));
            size_t instancedNodes = 0;
            for (const json& n : doc["nodes"]) instancedNodes += n.contains("extensions");
            EXPECT_EQ(instancedNodes, 3u);  // the Transform's own node, the root's batch, the Group's batch
            EXPECT_EQ(doc["extensionsUsed"], json::array({"EXT_mesh_gpu_instancing"}));
            EXPECT_EQ(doc["extensionsRequired"], json::array({"EXT_mesh_gpu_instancing"}));
        }
    }
}

TEST(GltfInstancing, FarTranslationsAndShearsAreWrittenAsInstanceNodes) {
    // 1e9 from a scene 10 across: float's translation would move it by tens of units.
    auto box = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>());
    auto root = make<Group>();
    auto far = make<Transform>(glm::translate(dmat4(1.0), dvec3(-1e9, 0, 0)));
    for (double x : {1e9 + 0.125, 1e9 + 3.0})
        far->addChild(make<Instance>(box, glm::translate(dmat4(1.0), dvec3(x, 0, 0))));
    root->addChild(far);
    const std::string path = tempPath("far.gltf");
    saveGltf(*root, path);
    EXPECT_EQ(readText(path).find("EXT_mesh_gpu_instancing"), std::string::npos);
    const GltfScene loaded = loadGltf(path);
    expectSameGraph(*root, *loaded.root);
    GltfSaveOptions off;  // and the writer can be told not to instance at all
    off.gpuInstancing = false;
    saveGltf(*instancedScene(3), path, off);
    EXPECT_EQ(readText(path).find("EXT_mesh_gpu_instancing"), std::string::npos);
}

TEST(GltfInstancing, KhronosValidatorFindsNoErrorInAWrittenFile) {
#ifndef SGKIT_TILES_TOOLS
    GTEST_SKIP() << "no SGKIT_TILES_TOOLS: build the tiles-tools target";
#else
    const fs::path modules = fs::path(SGKIT_TILES_TOOLS).parent_path().parent_path();
    if (!fs::exists(modules / "gltf-validator")) SG_SKIP_OR_FAIL("gltf-validator absent: build the tiles-tools target");
    const std::string file = tempPath("validate.glb"), out = tempPath("validate.json");
    saveGltf(*instancedScene(11), file);
    const std::string script =
        "import * as v from '" + (modules / "gltf-validator" / "module.mjs").string() +
        "'; import fs from 'fs'; const r = await v.validateBytes(new Uint8Array(fs.readFileSync('" + file +
        "')), {maxIssues: 100}); console.log(JSON.stringify({errors: r.issues.numErrors, "
        "messages: r.issues.messages.filter(m => m.severity === 0)}));";
    const std::string cmd = "node --input-type=module -e \"" + script + "\" > '" + out + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << readText(out);
    const json report = json::parse(readText(out));
    EXPECT_EQ(report["errors"], 0) << report.dump(1);
#endif
}

TEST(GltfInstancing, GltfpackInstancedOutputLoads) {
#ifndef SGKIT_TILES_TOOLS
    GTEST_SKIP() << "no SGKIT_TILES_TOOLS: build the tiles-tools target";
#else
    const fs::path cli = fs::path(SGKIT_TILES_TOOLS).parent_path().parent_path() / "gltfpack" / "cli.js";
    if (!fs::exists(cli)) SG_SKIP_OR_FAIL(cli << " absent: build the tiles-tools target");
    // Twenty nodes of one mesh, written without instancing: gltfpack -mi makes one instanced node of them.
    auto box = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>());
    auto root = make<Group>();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-20.0, 20.0);
    for (int i = 0; i < 20; ++i) {
        auto t = make<Transform>(glm::rotate(glm::translate(dmat4(1.0), dvec3(u(rng), u(rng), u(rng))), u(rng),
                                             glm::normalize(dvec3(u(rng), u(rng), 1.0))));
        t->addChild(box);
        root->addChild(t);
    }
    const std::string in = tempPath("pack_in.glb"), out = tempPath("pack_out.glb"), log = tempPath("pack.log");
    saveGltf(*root, in);
    const std::string cmd =
        "node '" + cli.string() + "' -i '" + in + "' -o '" + out + "' -mi -noq > '" + log + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << readText(log);
    const GltfScene packed = loadGltf(out);
    EXPECT_EQ(countKind(*packed.root, NodeKind::Instance), 20u);
    const Box a = worldBox(root), b = worldBox(packed.root);
    EXPECT_LT(glm::length(a.min - b.min), 1e-4);
    EXPECT_LT(glm::length(a.max - b.max), 1e-4);
#endif
}

// An sgkit LOD node with the extension (saveGltf writes Instances of an LOD of one level so): each instance is the
// LOD over the node's mesh, with its range and error; other readers draw the mesh at every instance.
TEST(GltfInstancing, AnInstancedLodPlacesTheLodOverItsMeshAtEachInstance) {
    const std::string lodExtras =
        R"(, "extras": {"sgkit": {"kind": "LOD", "center": [0, 0.5, 0], "ranges": [[2, 40]], "errors": [0.25]}})";
    const GltfScene s = instancedDoc(Trs{}, lodExtras).load();
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    ASSERT_EQ(s.root->numChildren(), 1u);
    const Node& holder = *s.root->child(0);
    ASSERT_EQ(holder.kind(), NodeKind::Transform);
    ASSERT_EQ(holder.numChildren(), 3u);
    const Node* proto = nullptr;
    for (size_t i = 0; i < 3; ++i) {
        ASSERT_EQ(holder.child(i)->kind(), NodeKind::Instance);
        const Node* p = static_cast<const Instance&>(*holder.child(i)).prototype();
        if (i == 0) proto = p;
        EXPECT_EQ(p, proto) << "one prototype for every instance";
    }
    ASSERT_EQ(proto->kind(), NodeKind::LOD);
    const auto& lod = static_cast<const LOD&>(*proto);
    ASSERT_EQ(lod.numChildren(), 1u);
    EXPECT_EQ(lod.child(0)->kind(), NodeKind::Geometry);
    EXPECT_EQ(lod.range(0).min, 2.0f);
    EXPECT_EQ(lod.range(0).max, 40.0f);
    EXPECT_TRUE(lod.hasErrors());
    EXPECT_EQ(lod.error(0), 0.25f);
    EXPECT_TRUE(lod.userCenter());
    EXPECT_EQ(lod.center(), dvec3(0, 0.5, 0));
    expectNear(static_cast<const Instance&>(*holder.child(0)).matrix(), glm::translate(dmat4(1.0), dvec3(1, 2, 3)),
               1e-12, "instance 0");

    struct Bad {
        const char* what;
        std::string node, path, reason;
    };
    const std::vector<Bad> cases = {
        {"two ranges", R"(, "extras": {"sgkit": {"kind": "LOD", "ranges": [[0, 10], [10, 20]]}})",
         "nodes[0].extras.sgkit.ranges", "needs one [min, max] range"},
        {"no ranges", R"(, "extras": {"sgkit": {"kind": "LOD"}})", "nodes[0].extras.sgkit.ranges",
         "needs one [min, max] range"},
        {"a range backwards", R"(, "extras": {"sgkit": {"kind": "LOD", "ranges": [[10, 2]]}})",
         "nodes[0].extras.sgkit.ranges", ""},
        {"errors of another length", R"(, "extras": {"sgkit": {"kind": "LOD", "ranges": [[0, 10]], "errors": [1, 2]}})",
         "nodes[0].extras.sgkit.errors", "needs one error per child (1)"},
        {"children", R"(, "children": [1], "extras": {"sgkit": {"kind": "LOD", "ranges": [[0, 10]]}})",
         "nodes[0].children", "an instanced sgkit LOD has no children"},
    };
    for (const Bad& c : cases) {
        SCOPED_TRACE(c.what);
        Doc d = instancedDoc(Trs{}, c.node);
        d.json.replace(d.json.rfind("]"), 1, R"(, {"mesh": 0}])");
        try {
            d.load();
            ADD_FAILURE() << "loaded";
        } catch (const LoadError& e) {
            EXPECT_EQ(e.jsonPath(), c.path) << e.what();
            EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.what();
        }
    }
}

// Many instances of one node are read into nested Groups of at most 32 nearby ones, so that the cull passes over
// a group out of view at once; every placement is kept.
TEST(GltfInstancing, ManyInstancesAreGroupedByPlace) {
    auto box = make<Geometry>(makeBoxMesh(dvec3(-0.5), dvec3(0.5)), make<Material>());
    auto root = make<Group>();
    auto field = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, 1)));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-500.0, 500.0);
    for (int i = 0; i < 1000; ++i)
        field->addChild(
            make<Instance>(box, glm::translate(dmat4(1.0), dvec3(std::floor(u(rng)), std::floor(u(rng)), 0))));
    root->addChild(field);
    const std::string path = tempPath("many.glb");
    saveGltf(*root, path);
    const GltfScene s = loadGltf(path);
    EXPECT_EQ(countKind(*s.root, NodeKind::Instance), 1000u);
    const auto da = draws(*root), db = draws(*s.root);
    ASSERT_EQ(da.size(), db.size());
    for (size_t i = 0; i < da.size(); ++i) expectNear(da[i].first, db[i].first, 1e-9, "draw " + std::to_string(i));
    // Leaf groups: at most 32 instances each, and each spread over far less than the field.
    size_t leaves = 0;
    std::function<void(const Node&)> walk = [&](const Node& n) {
        size_t instances = 0;
        Box at;
        for (size_t i = 0; i < n.numChildren(); ++i)
            if (n.child(i)->kind() == NodeKind::Instance) {
                ++instances;
                at.expand(dvec3(static_cast<const Instance&>(*n.child(i)).matrix()[3]));
            } else {
                walk(*n.child(i));
            }
        if (instances == 0) return;
        ++leaves;
        EXPECT_LE(instances, 32u);
        EXPECT_LT(std::max(at.max.x - at.min.x, at.max.y - at.min.y), 400.0);
    };
    walk(*s.root);
    EXPECT_GE(leaves, 1000u / 32u);
}
