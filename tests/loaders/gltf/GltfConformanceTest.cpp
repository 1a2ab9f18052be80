// glTF files as others write them: Debian's assimp-testmodels (sample models, exporters' output and files made
// broken on purpose), judged by the Khronos glTF validator (tests/loaders/gltf/validate_gltf.mjs). Every file it
// finds valid loads; every other one loads, with warnings, or is refused with a LoadError, never a crash. Small
// files glTF allows that tinygltf alone refuses (GltfAllowedFiles.h) pass the validator and load. And what saveGltf
// writes (motion too: GltfMotionScene.h) passes the validator.
#include "GltfAllowedFiles.h"
#include "GltfMotionScene.h"
#include "GltfTestUtil.h"
#include "OutsideTools.h"
#include "loaders/gltf/Gltf.h"
#include "nodes/Instance.h"
#include "testbed/Factory.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace {

using namespace sg;
using json = nlohmann::json;
namespace fs = std::filesystem;

const char* kModels = "/usr/share/assimp/models";

using testutil::npmModules;

// Why the validator cannot run here, or empty.
std::string validatorMissing() {
    const fs::path modules = npmModules();
    if (modules.empty() || !fs::exists(modules / "gltf-validator"))
        return "gltf-validator absent from '" + modules.string() +
               "': build the tiles-tools target or set SGKIT_NPM_MODULES";
    if (std::system("node --version > /dev/null 2>&1") != 0) return "node is not installed";
    return {};
}

struct Verdict {
    int errors = -1, warnings = 0;
    std::vector<std::string> messages, warningMessages;  // the first few
};

// The validator's verdict on each file, by path.
std::map<std::string, Verdict> validate(const std::vector<std::string>& files) {
    const std::string out =
        (fs::temp_directory_path() / ("sgkit_validate_" + std::to_string(::getpid()) + ".txt")).string();
    std::string cmd =
        "node '" SGKIT_SOURCE_DIR "/tests/loaders/gltf/validate_gltf.mjs' '" + npmModules().string() + "'";
    for (const std::string& f : files) cmd += " '" + f + "'";
    cmd += " > '" + out + "' 2>&1";
    const int status = std::system(cmd.c_str());
    std::ifstream in(out);
    std::map<std::string, Verdict> v;
    std::string line, all;
    while (std::getline(in, line)) {
        all += line + "\n";
        if (line.empty() || line[0] != '{') continue;
        const json j = json::parse(line);
        Verdict& d = v[j["file"].get<std::string>()];
        d.errors = j["errors"].get<int>();
        d.warnings = j["warnings"].get<int>();
        for (const auto& m : j["messages"]) d.messages.push_back(m.get<std::string>());
        for (const auto& m : j["warningMessages"]) d.warningMessages.push_back(m.get<std::string>());
    }
    std::remove(out.c_str());
    EXPECT_EQ(status, 0) << all;
    return v;
}

std::vector<std::string> thirdPartyFiles() {
    std::vector<std::string> files;
    for (const char* sub : {"glTF", "glTF2"}) {
        const fs::path dir = fs::path(kModels) / sub;
        if (!fs::is_directory(dir)) continue;
        for (const auto& e : fs::recursive_directory_iterator(dir)) {
            const std::string ext = e.path().extension().string();
            if (e.is_regular_file() && (ext == ".gltf" || ext == ".glb")) files.push_back(e.path().string());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

TEST(GltfConformance, FilesTheValidatorPassesLoadAndTheRestLoadOrAreRefused) {
    const std::vector<std::string> files = thirdPartyFiles();
    if (files.empty()) SG_SKIP_OR_FAIL("no glTF files under " << kModels << ": install assimp-testmodels");
    if (const std::string why = validatorMissing(); !why.empty()) SG_SKIP_OR_FAIL(why);
    const std::map<std::string, Verdict> verdicts = validate(files);
    int valid = 0, validLoaded = 0, validUnsupported = 0, invalidLoaded = 0, invalidRefused = 0;
    for (const std::string& f : files) {
        const auto found = verdicts.find(f);
        ASSERT_NE(found, verdicts.end()) << f << ": no verdict";
        const Verdict& v = found->second;
        const std::string name = fs::relative(f, kModels).string();
        std::string outcome;
        try {
            const GltfScene s = loadGltf(f);
            outcome = "loaded, " + std::to_string(s.warnings.size()) + " warnings" +
                      (s.warnings.empty() ? "" : " (first: " + s.warnings.front() + ")");
            if (v.errors == 0)
                ++validLoaded;
            else
                ++invalidLoaded;
        } catch (const LoadError& e) {
            outcome = std::string("refused: ") + e.what();
            // A valid file may require an extension sgkit does not implement: refused, naming it.
            const bool unsupported = e.jsonPath().rfind("extensionsRequired[", 0) == 0;
            EXPECT_TRUE(v.errors != 0 || unsupported)
                << name << ": the validator finds no error, the loader refuses it: " << e.what();
            if (v.errors != 0)
                ++invalidRefused;
            else
                ++validUnsupported;
        }
        valid += v.errors == 0;
        std::printf("[ conformance ] %-72s validator %d errors%s | %s\n", name.c_str(), v.errors,
                    v.messages.empty() ? "" : (" (" + v.messages.front().substr(0, 90) + ")").c_str(),
                    outcome.substr(0, 200).c_str());
    }
    std::printf(
        "[ conformance ] %zu files: %d valid (%d loaded, %d needing an unsupported extension), %zu invalid (%d "
        "loaded, %d refused)\n",
        files.size(), valid, validLoaded, validUnsupported, files.size() - size_t(valid), invalidLoaded,
        invalidRefused);
    EXPECT_EQ(validLoaded + validUnsupported, valid);
    EXPECT_EQ(validUnsupported, 0);  // KHR_technique_webgl, a shading extension, loads with the nearest material
}

// --- Files glTF allows that tinygltf alone refuses or misreads (GltfAllowedFiles.h)

using gltfallowed::Allowed;
using gltfallowed::allowedFiles;

// Loads a case, checks it against what it expects, and says what happened.
std::string judge(const Allowed& c, const std::function<GltfScene()>& load) {
    try {
        const GltfScene s = load();
        EXPECT_EQ(c.refusedAt, "") << c.file << ": loaded";
        std::string all;
        for (const std::string& w : s.warnings) all += "\n  " + w;
        if (c.warning.empty())
            EXPECT_TRUE(s.warnings.empty()) << c.file << all;
        else
            EXPECT_NE(all.find(c.warning), std::string::npos)
                << c.file << ": no warning with '" << c.warning << "'" << all;
        if (c.check) c.check(s);
        return "loaded, " + std::to_string(s.warnings.size()) + " warnings" +
               (s.warnings.empty() ? "" : " (first: " + s.warnings.front() + ")");
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath(), c.refusedAt) << c.file << ": " << e.what();
        return std::string("refused: ") + e.what();
    }
}

TEST(GltfConformance, FilesGltfAllowsLoad) {  // no validator needed
    for (const Allowed& c : allowedFiles())
        judge(c, [&] { return loadGltfFromMemory(c.file, c.bytes.data(), c.bytes.size()); });
}

TEST(GltfConformance, FilesGltfAllowsPassTheValidatorAndLoad) {
    if (const std::string why = validatorMissing(); !why.empty()) SG_SKIP_OR_FAIL(why);
    const fs::path dir = fs::temp_directory_path() / ("sgkit_gltf_allowed_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::vector<Allowed> cases = allowedFiles();
    std::vector<std::string> files;
    for (const Allowed& c : cases) {
        files.push_back((dir / c.file).string());
        std::ofstream(files.back(), std::ios::binary) << c.bytes;
    }
    const std::map<std::string, Verdict> verdicts = validate(files);
    for (size_t i = 0; i < cases.size(); ++i) {
        const auto v = verdicts.find(files[i]);
        ASSERT_NE(v, verdicts.end()) << files[i];
        const Verdict& d = v->second;
        // Each file is what it claims: valid, or (a fraction for an integer) not.
        EXPECT_EQ(d.errors != 0, cases[i].validatorErrors) << cases[i].file;
        const std::string outcome = judge(cases[i], [&] { return loadGltf(files[i]); });
        const std::string said = !d.messages.empty()          ? " (" + d.messages.front() + ")"
                                 : !d.warningMessages.empty() ? " (warns " + d.warningMessages.front() + ")"
                                                              : "";
        std::printf("[ conformance ] %-40s validator %d errors, %d warnings%s | %s\n", cases[i].file.c_str(), d.errors,
                    d.warnings, said.substr(0, 100).c_str(), outcome.substr(0, 160).c_str());
    }
    fs::remove_all(dir);
}

// A buffer on the network is not fetched: the load is refused naming the URI (a local file's loads never wait on
// a server; tilesets fetch their contents through sg::readResource instead).
TEST(GltfConformance, UrisOnTheNetworkAreNotFetched) {
    gltftest::Doc d;
    d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}])";
    const fs::path dir = fs::temp_directory_path() / ("sgkit_gltf_url_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string path = (dir / "box.gltf").string();
    for (const char* url : {"http://example.com/models/box.bin", "https://example.com/box.bin"}) {
        d.externalBin = url;
        std::ofstream(path) << d.text();
        try {
            loadGltf(path);
            ADD_FAILURE() << "loaded a buffer from " << url;
        } catch (const LoadError& e) {
            EXPECT_NE(e.reason().find(url), std::string::npos) << e.what();
            EXPECT_NE(e.reason().find("network"), std::string::npos) << e.what();
        }
    }
    // An image so is not fetched either; like any image that cannot be read, its texture is skipped with a warning.
    d.externalBin.clear();
    d.json = R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "images": [{"uri": "http://example.com/t.png"}],
                "textures": [{"source": 0}], "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}])";
    std::ofstream(path) << d.text();
    const GltfScene s = loadGltf(path);
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    EXPECT_NE(all.find("'http://example.com/t.png' is on the network"), std::string::npos) << all;
    fs::remove_all(dir);
}

struct Written {
    std::string name;
    ref_ptr<Node> root;
    std::vector<ref_ptr<Animation>> animations;
};

// Skins of 4 and 8 influences, morph targets with weights, and an animation of every path and interpolation with a
// KHR_animation_pointer channel (GltfMotionScene.h).
Written motionWritten() {
    gltftest::MotionScene s = gltftest::motionScene();
    AnimationSampler colour;
    colour.times = {0, 1};
    colour.values = {1, 1, 1, 1, 1, 0, 0, 1};
    colour.width = 4;
    s.animation->samplers.push_back(colour);
    AnimationChannel c;
    c.sampler = uint32_t(s.animation->samplers.size() - 1);
    c.path = AnimationPath::Property;
    c.set = [](const double*, uint32_t) {};
    c.target = "/materials/0/pbrMetallicRoughness/baseColorFactor";  // the scene has one material
    s.animation->channels.push_back(c);
    return {"motion", s.root, {s.animation}};
}

// Scenes as sgkit's users write them: a small factory (LODs, switches, billboards, instances, terrain), textures,
// physical materials with every map, EXT_mesh_gpu_instancing, skins, morph targets and animations; each as .glb and
// .gltf.
std::vector<Written> writtenScenes() {
    std::vector<Written> out;
    scenes::FactoryParams small;
    small.siteSize = 600.0;
    small.terrainCells = 64;
    small.terrainTiles = 4;
    small.machinesPerWorkshop = 3;
    small.trees = 12;
    small.cars = 4;
    out.push_back({"factory", scenes::buildFactory(small).root, {}});
    out.push_back({"kinds", gltftest::allKindsScene(), {}});

    std::vector<uint8_t> px(16 * 16 * 4);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 37 % 251);
    auto tex = make<Texture>(16, 16, px);
    auto textured = make<Group>();
    textured->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>(vec4(1.0f), tex)));
    out.push_back({"textured", textured, {}});

    auto mesh = makeBoxMesh(dvec3(-1), dvec3(1), 2);
    std::vector<vec2> uv1;
    for (const vec2& t : mesh->uvs()) uv1.push_back(t * 0.5f);
    mesh->setSurface(generateTangents(*mesh, 0), uv1);
    auto pbr = make<Material>(vec4(0.9f, 0.8f, 0.7f, 1.0f), tex);
    pbr->physical = true;
    pbr->pbr.metallic = 0.3f;
    pbr->pbr.roughness = 0.6f;
    pbr->pbr.metallicRoughness.texture = tex;
    pbr->pbr.normal.texture = tex;
    pbr->pbr.normalScale = 0.8f;
    pbr->pbr.occlusion.texture = tex;
    pbr->pbr.occlusion.texCoord = 1;
    pbr->pbr.emissive.texture = tex;
    pbr->pbr.emissiveFactor = vec3(0.2f, 0.1f, 0.0f);
    pbr->textureTransform = mat3(glm::scale(glm::mat4(1.0f), glm::vec3(2.0f, 2.0f, 1.0f)));
    pbr->textureTransform[2] = vec3(0.25f, 0.5f, 1.0f);
    auto blended = make<Material>(vec4(0.2f, 0.4f, 0.9f, 0.5f));
    blended->physical = true;
    blended->blend = true;
    blended->doubleSided = false;
    auto physical = make<Group>();
    physical->addChild(make<Geometry>(mesh, pbr));
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(3, 0, 0)));
    t->addChild(make<Geometry>(mesh, blended));
    physical->addChild(t);
    out.push_back({"physical", physical, {}});

    auto box = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>(vec4(0.8f, 0.3f, 0.2f, 1.0f)));
    auto instanced = make<Group>();
    for (int i = 0; i < 8; ++i)
        instanced->addChild(make<Instance>(
            box, glm::scale(glm::rotate(glm::translate(dmat4(1.0), dvec3(i * 3.0, 0, i % 3)), 0.2 * i, dvec3(0, 1, 0)),
                            dvec3(1.0 + 0.1 * i))));
    out.push_back({"instanced", instanced, {}});
    out.push_back(motionWritten());
    return out;
}

TEST(GltfConformance, WhatSaveGltfWritesPassesTheValidator) {
    if (const std::string why = validatorMissing(); !why.empty()) SG_SKIP_OR_FAIL(why);
    const fs::path dir = fs::temp_directory_path() / ("sgkit_gltf_written_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::vector<std::string> files;
    for (const Written& w : writtenScenes())
        for (const char* ext : {".glb", ".gltf"}) {
            files.push_back((dir / (w.name + ext)).string());
            std::vector<std::string> warnings;
            GltfSaveOptions options;
            options.animations = w.animations;
            options.warnings = &warnings;
            saveGltf(*w.root, files.back(), options);
            if (!w.animations.empty()) {
                EXPECT_EQ(warnings.size(), 0u) << files.back() << ": " << (warnings.empty() ? "" : warnings.front());
            }
        }
    const std::map<std::string, Verdict> verdicts = validate(files);
    for (const std::string& f : files) {
        const auto v = verdicts.find(f);
        ASSERT_NE(v, verdicts.end()) << f;
        std::string why;
        for (const std::string& m : v->second.messages) why += "\n  " + m;
        EXPECT_EQ(v->second.errors, 0) << f << why;
        std::printf("[ conformance ] written %-16s %d errors, %d warnings%s\n", fs::path(f).filename().c_str(),
                    v->second.errors, v->second.warnings,
                    v->second.warningMessages.empty() ? "" : (" (" + v->second.warningMessages.front() + ")").c_str());
    }
    fs::remove_all(dir);
}

}  // namespace
