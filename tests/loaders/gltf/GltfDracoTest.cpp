// KHR_draco_mesh_compression: files made here with Draco's own encoder load with the values the encoder's
// quantization promises; broken streams and files that disagree with their stream are refused, naming the
// primitive's extension.
#include "GltfTestUtil.h"
#include "OutsideTools.h"
#include "loaders/gltf/Gltf.h"
#include "sg/scene/internal/DistinctGeometries.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <draco/point_cloud/point_cloud_builder.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>

namespace {

using namespace sg;
using json = nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kExt = "KHR_draco_mesh_compression";
constexpr int kPositionBits = 14, kNormalBits = 10, kUvBits = 12;

// A UV sphere: seams and poles give points of one position with several texture coordinates.
struct Original {
    std::vector<vec3> positions, normals;
    std::vector<vec2> uvs;
    std::vector<uint32_t> indices;
};

Original sphere(int segments, int rings, float radius) {
    Original o;
    const float pi = 3.14159265f;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            // Pole rows hold one point per segment, at its middle in u: no triangle is degenerate.
            const float u = (r == 0 || r == rings) ? (float(s) + 0.5f) / float(segments) : float(s) / float(segments);
            const float v = float(r) / float(rings), theta = u * 2.0f * pi, phi = v * pi;
            const vec3 n(std::sin(phi) * std::cos(theta), std::cos(phi), std::sin(phi) * std::sin(theta));
            o.positions.push_back(n * radius + vec3(0.5f, -2.0f, 3.0f));
            o.normals.push_back(n);
            o.uvs.push_back(vec2(u, v));
        }
    const auto at = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            if (r != 0) o.indices.insert(o.indices.end(), {at(r, s), at(r, s + 1), at(r + 1, s)});
            if (r != rings - 1) o.indices.insert(o.indices.end(), {at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)});
        }
    return o;
}

struct Encoded {
    std::string bytes;
    int position = -1, normal = -1, uv = -1;  // the attributes' Draco unique ids
    size_t points = 0, faces = 0;             // as a decoder finds them (what the file's accessors declare)
};

Encoded encode(const Original& o, int speed = 5) {
    draco::TriangleSoupMeshBuilder b;
    const int faces = int(o.indices.size() / 3);
    b.Start(faces);
    const int pos = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    const int nor = b.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
    const int tex = b.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
    for (int f = 0; f < faces; ++f) {
        const uint32_t* i = &o.indices[size_t(f) * 3];
        const draco::FaceIndex fi{uint32_t(f)};
        b.SetAttributeValuesForFace(pos, fi, &o.positions[i[0]], &o.positions[i[1]], &o.positions[i[2]]);
        b.SetAttributeValuesForFace(nor, fi, &o.normals[i[0]], &o.normals[i[1]], &o.normals[i[2]]);
        b.SetAttributeValuesForFace(tex, fi, &o.uvs[i[0]], &o.uvs[i[1]], &o.uvs[i[2]]);
    }
    std::unique_ptr<draco::Mesh> mesh = b.Finalize();
    EXPECT_TRUE(mesh);
    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, kPositionBits);
    enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, kNormalBits);
    enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, kUvBits);
    enc.SetSpeedOptions(speed, speed);
    draco::EncoderBuffer buffer;
    const draco::Status st = enc.EncodeMeshToBuffer(*mesh, &buffer);
    EXPECT_TRUE(st.ok()) << st.error_msg_string();
    Encoded e;
    e.bytes.assign(buffer.data(), buffer.size());
    e.position = int(mesh->attribute(pos)->unique_id());
    e.normal = int(mesh->attribute(nor)->unique_id());
    e.uv = int(mesh->attribute(tex)->unique_id());
    draco::DecoderBuffer in;
    in.Init(e.bytes.data(), e.bytes.size());
    auto decoded = draco::Decoder().DecodeMeshFromBuffer(&in);
    EXPECT_TRUE(decoded.ok());
    e.points = decoded.value()->num_points();
    e.faces = decoded.value()->num_faces();
    return e;
}

// The glTF document of one primitive whose geometry is the stream `e` (accessors without buffer views, as the
// extension has them); `edit` may change it before it is written.
json document(const Encoded& e) {
    json j;
    j["asset"] = {{"version", "2.0"}};
    j["extensionsUsed"] = {kExt};
    j["extensionsRequired"] = {kExt};
    j["scene"] = 0;
    j["scenes"] = json::array({{{"nodes", {0}}}});
    j["nodes"] = json::array({{{"mesh", 0}}});
    json prim = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}, {"indices", 3}};
    prim["extensions"][kExt] = {{"bufferView", 0},
                                {"attributes", {{"POSITION", e.position}, {"NORMAL", e.normal}, {"TEXCOORD_0", e.uv}}}};
    j["meshes"] = json::array({{{"primitives", {prim}}}});
    j["accessors"] = json::array({{{"componentType", 5126}, {"count", e.points}, {"type", "VEC3"}},
                                  {{"componentType", 5126}, {"count", e.points}, {"type", "VEC3"}},
                                  {{"componentType", 5126}, {"count", e.points}, {"type", "VEC2"}},
                                  {{"componentType", 5125}, {"count", e.faces * 3}, {"type", "SCALAR"}}});
    j["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", e.bytes.size()}}});
    j["buffers"] = json::array({{{"byteLength", e.bytes.size()},
                                 {"uri", "data:application/octet-stream;base64," + gltftest::base64(e.bytes)}}});
    return j;
}

GltfScene load(const json& j) {
    const std::string text = j.dump();
    return loadGltfFromMemory("draco.gltf", text.data(), text.size());
}

// The one mesh of a loaded scene.
const Mesh& onlyMesh(const GltfScene& s) {
    const Mesh* found = nullptr;
    int n = 0;
    forEachDistinctGeometry(*s.root, [&](const Geometry& g) {
        found = g.mesh();
        ++n;
    });
    EXPECT_EQ(n, 1);
    if (!found) throw std::runtime_error("no mesh");
    return *found;
}

// Triangles as corner ids rotated to start at the smallest (Draco may reorder triangles and rotate corners, but
// keeps their winding), sorted.
std::vector<std::array<uint32_t, 3>> canonical(const std::vector<uint32_t>& idx) {
    std::vector<std::array<uint32_t, 3>> t;
    for (size_t i = 0; i + 2 < idx.size(); i += 3) {
        std::array<uint32_t, 3> a{idx[i], idx[i + 1], idx[i + 2]};
        std::rotate(a.begin(), std::min_element(a.begin(), a.end()), a.end());
        t.push_back(a);
    }
    std::sort(t.begin(), t.end());
    return t;
}

float maxAbs(const vec3& a) { return std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z)}); }

// How far a decoded mesh is from the original: each decoded point is matched to the nearest original one (by
// position, UV and normal: a box's corner is three points); the largest component differences, the largest normal
// angle, and whether the triangles (through the match, as canonical()) are the original ones.
struct Errors {
    float position = 0.0f, uv = 0.0f, normalDegrees = 0.0f;
    bool sameTriangles = false;
};

Errors compare(const Mesh& m, const Original& o) {
    Errors e;
    std::vector<uint32_t> toOriginal(m.positions().size());
    const bool uvs = !o.uvs.empty() && m.uvs().size() == m.positions().size();
    const bool normals = !o.normals.empty() && m.normals().size() == m.positions().size();
    for (size_t i = 0; i < m.positions().size(); ++i) {
        size_t best = 0;
        float bestD = 1e30f;
        for (size_t k = 0; k < o.positions.size(); ++k) {
            const float d = glm::length(m.positions()[i] - o.positions[k]) +
                            (uvs ? glm::length(m.uvs()[i] - o.uvs[k]) : 0.0f) +
                            (normals ? glm::length(m.normals()[i] - o.normals[k]) : 0.0f);
            if (d < bestD) bestD = d, best = k;
        }
        toOriginal[i] = uint32_t(best);
        e.position = std::max(e.position, maxAbs(m.positions()[i] - o.positions[best]));
        if (uvs) {
            const vec2 du = glm::abs(m.uvs()[i] - o.uvs[best]);
            e.uv = std::max({e.uv, du.x, du.y});
        }
        if (normals) {
            const float c = glm::dot(glm::normalize(m.normals()[i]), o.normals[best]);
            e.normalDegrees = std::max(e.normalDegrees, std::acos(std::min(1.0f, c)) * 57.29578f);
        }
    }
    std::vector<uint32_t> mapped;
    for (uint32_t t = 0; t < m.indexCount(); ++t) mapped.push_back(toOriginal[m.index(t)]);
    e.sameTriangles = canonical(mapped) == canonical(o.indices);
    return e;
}

// The extension's path in messages about the first primitive.
const std::string kPath = std::string("meshes[0].primitives[0].extensions.") + kExt;

void expectRefused(const json& j, const std::string& path, const std::string& reasonPart) {
    SCOPED_TRACE(path + ": " + reasonPart);
    try {
        load(j);
        ADD_FAILURE() << "loaded; expected a refusal at " << path;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath().rfind(path, 0), 0u) << e.what();
        EXPECT_NE(e.reason().find(reasonPart), std::string::npos) << e.what();
    }
}

// Every decoded point is an original one within the quantization's bound (Draco's uniform quantization rounds to
// the nearest of 2^bits - 1 steps over the attribute's largest extent: at most half a step off per component;
// normals are octahedral, compared by angle), and the triangles are the original ones.
TEST(GltfDraco, DecodedMeshIsTheOriginalWithinTheQuantizationBound) {
    const Original o = sphere(24, 12, 2.0f);
    for (int speed : {0, 5, 10}) {  // edgebreaker (valence, standard) and sequential encodings
        SCOPED_TRACE("speed " + std::to_string(speed));
        const Encoded e = encode(o, speed);
        const GltfScene s = load(document(e));
        EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
        const Mesh& m = onlyMesh(s);
        ASSERT_EQ(m.positions().size(), e.points);
        ASSERT_EQ(m.normals().size(), e.points);
        ASSERT_EQ(m.uvs().size(), e.points);
        ASSERT_EQ(m.triangleCount(), o.indices.size() / 3);

        const float posStep = 4.0f / float((1 << kPositionBits) - 1);  // the sphere's extent is its diameter, 4
        const float uvStep = 1.0f / float((1 << kUvBits) - 1);
        const Errors err = compare(m, o);
        EXPECT_LE(err.position, 0.5f * posStep * 1.001f);
        EXPECT_LE(err.uv, 0.5f * uvStep * 1.001f);
        // 10-bit octahedral normals: the grid's diagonal is about 0.2 degrees at its coarsest.
        EXPECT_LE(err.normalDegrees, 0.25f);
        EXPECT_TRUE(err.sameTriangles);
        std::printf(
            "[ draco ] speed %d: %zu bytes for %zu points, %u triangles; max error position %.3g (bound %.3g), "
            "uv %.3g (bound %.3g), normal %.3f deg\n",
            speed, e.bytes.size(), e.points, m.triangleCount(), double(err.position), double(0.5f * posStep),
            double(err.uv), double(0.5f * uvStep), double(err.normalDegrees));
    }
}

// Two primitives of one stream (as encoders write repeated geometry) share their decoded accessors: one mesh.
TEST(GltfDraco, PrimitivesSharingAStreamShareTheirDecodedMesh) {
    const Encoded e = encode(sphere(8, 4, 1.0f));
    json j = document(e);
    j["meshes"].push_back(j["meshes"][0]);
    j["nodes"] = json::array({{{"children", {1, 2}}}, {{"mesh", 0}}, {{"mesh", 1}, {"translation", {3, 0, 0}}}});
    const GltfScene s = load(j);
    std::set<const Mesh*> meshes;
    int geometries = 0;
    std::function<void(const Node&)> walk = [&](const Node& n) {
        if (auto g = dynamic_cast<const Geometry*>(&n)) meshes.insert(g->mesh()), ++geometries;
        for (size_t i = 0; i < n.numChildren(); ++i) walk(*n.child(i));
    };
    walk(*s.root);
    EXPECT_EQ(geometries, 2);
    EXPECT_EQ(meshes.size(), 1u);
}

TEST(GltfDraco, CorruptStreamsAreRefusedNamingTheExtension) {
    const Encoded e = encode(sphere(16, 8, 1.0f));
    {
        Encoded bad = e;
        bad.bytes = "not a draco stream at all";
        expectRefused(document(bad), kPath, "Draco");
    }
    for (size_t keep : {size_t(0), size_t(4), size_t(10), e.bytes.size() / 2, e.bytes.size() - 1}) {
        SCOPED_TRACE("cut to " + std::to_string(keep) + " bytes");
        Encoded bad = e;
        bad.bytes.resize(keep);
        if (keep == 0) {  // an empty view: tinygltf or the decoder refuses it
            EXPECT_THROW(load(document(bad)), LoadError);
            continue;
        }
        expectRefused(document(bad), kPath, "");
    }
    // Bytes changed at random, anywhere and then in the first 64 (the header, method and counts a decoder sizes its
    // arrays by): loaded (the values changed) or refused with the path, never a crash.
    std::mt19937 rng(27);
    for (size_t span : {e.bytes.size(), size_t(64)}) {
        int refused = 0, loaded = 0;
        const int trials = span == 64 ? 2000 : 300;
        for (int trial = 0; trial < trials; ++trial) {
            Encoded bad = e;
            const int flips = 1 + int(rng() % 4);
            for (int f = 0; f < flips; ++f) bad.bytes[rng() % span] ^= char(1 + rng() % 255);
            try {
                load(document(bad));
                ++loaded;
            } catch (const LoadError& err) {
                ++refused;
                EXPECT_EQ(err.jsonPath().rfind("meshes[0].primitives[0]", 0), 0u) << err.what();
            }
        }
        std::printf("[ draco ] %d streams changed in their first %zu bytes: %d refused, %d loaded\n", trials, span,
                    refused, loaded);
        EXPECT_GT(refused, 0);
    }
}

TEST(GltfDraco, FilesThatDisagreeWithTheirStreamAreRefused) {
    const Encoded e = encode(sphere(8, 4, 1.0f));
    json j = document(e);
    j["accessors"][0]["count"] = e.points + 1;
    expectRefused(j, kPath + ".attributes.POSITION", "declares");
    j = document(e);
    j["accessors"][3]["count"] = e.faces * 3 - 3;
    expectRefused(j, kPath, "indices");
    j = document(e);
    j["meshes"][0]["primitives"][0]["extensions"][kExt]["attributes"]["NORMAL"] = 17;
    expectRefused(j, kPath + ".attributes.NORMAL", "no attribute with id 17");
    j = document(e);
    j["meshes"][0]["primitives"][0]["extensions"][kExt]["attributes"]["COLOR_0"] = e.uv;
    expectRefused(j, kPath + ".attributes.COLOR_0", "no attribute COLOR_0");
    j = document(e);
    j["accessors"][2]["type"] = "VEC3";  // the stream's TEXCOORD_0 has 2 components
    expectRefused(j, kPath + ".attributes.TEXCOORD_0", "components");
    const Encoded big = encode(sphere(24, 12, 1.0f));
    ASSERT_GT(big.points, 256u);
    j = document(big);
    j["accessors"][3]["componentType"] = 5121;  // more points than an unsigned byte indexes
    expectRefused(j, kPath, "index");
    j = document(e);
    j["meshes"][0]["primitives"][0]["extensions"][kExt]["bufferView"] = 5;
    expectRefused(j, kPath + ".bufferView", "buffer view");
    j = document(e);
    j["meshes"][0]["primitives"][0]["mode"] = 0;  // points, but the stream is a triangle mesh
    expectRefused(j, kPath, "triangle mesh");
    j = document(e);
    j["meshes"][0]["primitives"][0]["extensions"][kExt] = 3;  // tinygltf drops it: accessors without data remain
    EXPECT_THROW(load(j), LoadError);
}

// A Draco point cloud (mode POINTS) decodes like a mesh and loads as points, in the stream's order. The same stream
// read as triangles is refused.
TEST(GltfDraco, PointCloudsDecodeAndLoadAsPoints) {
    draco::PointCloudBuilder b;
    b.Start(50);
    const int pos = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    for (uint32_t i = 0; i < 50; ++i) {
        const vec3 p(float(i), std::sin(float(i)), 0.5f * float(i % 7));
        b.SetAttributeValueForPoint(pos, draco::PointIndex(i), &p);
    }
    std::unique_ptr<draco::PointCloud> cloud = b.Finalize(false);
    ASSERT_TRUE(cloud);
    draco::EncoderBuffer buffer;
    ASSERT_TRUE(draco::Encoder().EncodePointCloudToBuffer(*cloud, &buffer).ok());
    Encoded e;
    e.bytes.assign(buffer.data(), buffer.size());
    e.position = int(cloud->attribute(pos)->unique_id());
    e.points = 50;
    json j = document(e);
    auto& prim = j["meshes"][0]["primitives"][0];
    prim.erase("indices");
    prim["mode"] = 0;
    prim["attributes"] = {{"POSITION", 0}};
    prim["extensions"][kExt]["attributes"] = {{"POSITION", e.position}};
    j["accessors"] = json::array({j["accessors"][0]});
    const GltfScene s = load(j);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
    const Mesh& m = onlyMesh(s);
    EXPECT_EQ(m.primitive(), Primitive::Points);
    ASSERT_EQ(m.pointCount(), 50u);
    // Draco may reorder the points; with no quantization asked for, each x is still its whole number.
    std::multiset<float> xs;
    for (const vec3& p : m.positions()) xs.insert(std::round(p.x));
    for (uint32_t i = 0; i < 50; ++i) EXPECT_EQ(xs.count(float(i)), 1u) << i;
    prim["mode"] = 4;
    expectRefused(j, kPath, "no triangle mesh");
}

// The Draco-compressed 2CylinderEngine of Debian's assimp-testmodels (written by COLLADA2GLTF and Draco's glTF
// tools, not here) loads with, within its quantization, the bounds of the uncompressed one.
TEST(GltfDraco, ThirdPartyEngineModelMatchesItsUncompressedOriginal) {
    const std::string dir = "/usr/share/assimp/models/glTF2/";
    const std::string draco = dir + "draco/2CylinderEngine.gltf",
                      plain = dir + "2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    if (!fs::exists(draco) || !fs::exists(plain)) SG_SKIP_OR_FAIL(draco << " absent: install assimp-testmodels");
    const GltfScene a = loadGltf(draco), b = loadGltf(plain);
    // Triangles drawn (a mesh once per path to it) and the world box of the graph.
    auto measure = [](const GltfScene& s, size_t& triangles, Box& box) {
        std::function<void(const Node&, const dmat4&)> walk = [&](const Node& n, const dmat4& m) {
            dmat4 world = m;
            if (auto t = dynamic_cast<const Transform*>(&n)) world = m * t->matrix();
            if (auto g = dynamic_cast<const Geometry*>(&n)) {
                triangles += g->mesh()->triangleCount();
                for (const vec3& p : g->mesh()->positions()) box.expand(dvec3(world * dvec4(dvec3(p), 1.0)));
            }
            for (size_t i = 0; i < n.numChildren(); ++i) walk(*n.child(i), world);
        };
        walk(*s.root, dmat4(1.0));
    };
    size_t ta = 0, tb = 0;
    Box ba, bb;
    measure(a, ta, ba);
    measure(b, tb, bb);
    // The compressed file has fewer triangles (its accessors declare 65,311 to the original's 75,730: Draco's
    // encoder drops degenerate ones); the decoder's count must equal the declared one, or the load is refused.
    EXPECT_LE(ta, tb);
    EXPECT_GT(ta, tb * 85 / 100);
    const double extent = glm::length(bb.max - bb.min);
    EXPECT_LT(glm::length(ba.min - bb.min), 1e-4 * extent);
    EXPECT_LT(glm::length(ba.max - bb.max), 1e-4 * extent);
    std::printf(
        "[ draco ] 2CylinderEngine: %zu triangles drawn (uncompressed %zu); box corners %.3g and %.3g apart (extent "
        "%.4g)\n",
        ta, tb, glm::length(ba.min - bb.min), glm::length(ba.max - bb.max), extent);
}

// Another encoder: Cesium's gltf-pipeline (npm; Draco's JavaScript build) compresses a file saveGltf wrote. Each
// mesh loads back within the quantization asked for, with the same triangles.
TEST(GltfDraco, GltfPipelineOutputMatchesWhatWasSaved) {
    const char* env = std::getenv("SGKIT_NPM_MODULES");
#ifdef SGKIT_NPM_MODULES
    const fs::path modules = env ? env : SGKIT_NPM_MODULES;
#else
    const fs::path modules = env ? env : "";
#endif
    const fs::path tool = modules / "gltf-pipeline" / "bin" / "gltf-pipeline.js";
    if (!fs::exists(tool)) SG_SKIP_OR_FAIL(tool << " absent: tools/fetch-tiles-tools.sh installs it");
    if (std::system("node --version > /dev/null 2>&1") != 0) SG_SKIP_OR_FAIL("node is not installed");

    const Original sph = sphere(24, 12, 2.0f);
    auto sphereMesh = make<Mesh>();
    sphereMesh->set(sph.positions, sph.normals, sph.indices, sph.uvs);
    auto box = makeBoxMesh(dvec3(-1, -2, -3), dvec3(3, 2, 1), 2);
    auto root = make<Group>();
    root->addChild(make<Geometry>(sphereMesh, make<Material>()));
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(10, 0, 0)));
    t->addChild(make<Geometry>(box, make<Material>(vec4(0.2f, 0.5f, 0.9f, 1.0f))));
    root->addChild(t);

    const fs::path dir = fs::temp_directory_path() / ("sgkit_draco_pipeline_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string in = (dir / "in.glb").string(), out = (dir / "out.glb").string();
    saveGltf(*root, in);
    const std::string cmd = "node '" + tool.string() + "' -i '" + in + "' -o '" + out + "' -d" +
                            " --draco.quantizePositionBits " + std::to_string(kPositionBits) +
                            " --draco.quantizeNormalBits " + std::to_string(kNormalBits) +
                            " --draco.quantizeTexcoordBits " + std::to_string(kUvBits) + " > '" + out + ".log' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream f(out, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    ASSERT_NE(bytes.find(kExt), std::string::npos) << "gltf-pipeline wrote no Draco";

    const GltfScene s = loadGltf(out);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    std::vector<const Mesh*> loaded;
    forEachDistinctGeometry(*s.root, [&](const Geometry& g) { loaded.push_back(g.mesh()); });
    ASSERT_EQ(loaded.size(), 2u);
    for (const Mesh* m : loaded) {
        const bool isSphere = m->triangleCount() == sphereMesh->triangleCount();
        const Mesh& original = isSphere ? *sphereMesh : *box;
        ASSERT_EQ(m->triangleCount(), original.triangleCount());
        Original o;
        o.positions = original.positions();
        o.normals = original.normals();
        o.uvs = original.uvs();
        for (uint32_t i = 0; i < original.indexCount(); ++i) o.indices.push_back(original.index(i));
        const Errors err = compare(*m, o);
        const dvec3 size = original.box().max - original.box().min;
        const float posStep = float(std::max({size.x, size.y, size.z})) / float((1 << kPositionBits) - 1);
        EXPECT_LE(err.position, 0.5f * posStep * 1.001f) << (isSphere ? "sphere" : "box");
        EXPECT_LE(err.uv, 0.5f / float((1 << kUvBits) - 1) * 1.001f);
        EXPECT_LE(err.normalDegrees, 0.25f);
        EXPECT_TRUE(err.sameTriangles);
        std::printf("[ draco ] gltf-pipeline %s: max error position %.3g (bound %.3g), uv %.3g, normal %.3f deg\n",
                    isSphere ? "sphere" : "box", double(err.position), double(0.5f * posStep), double(err.uv),
                    double(err.normalDegrees));
    }
    std::printf("[ draco ] gltf-pipeline: %zu bytes saved, %zu compressed\n", size_t(fs::file_size(in)), bytes.size());
    fs::remove_all(dir);
}

// libdraco.a holds its own copy of tinygltf and stb: the loader must run Debian's (the link order in
// CMakeLists.txt), whose definitions are then the ones the process resolves.
TEST(GltfDraco, TinygltfAndStbAreTheirOwnLibrariesNotDracosCopies) {
    const std::pair<const char*, const char*> symbols[] = {
        {"_ZN8tinygltf8TinyGLTF20LoadBinaryFromMemoryEPNS_5ModelEPNSt7__cxx1112basic_stringIcSt11char_"
         "traitsIcESaIcEEES9_PKhjRKS8_j",
         "libtinygltf"},
        {"stbi_failure_reason", "libstb"}};
    for (const auto& [symbol, library] : symbols) {
        void* p = dlsym(RTLD_DEFAULT, symbol);
        ASSERT_NE(p, nullptr) << symbol;
        Dl_info info{};
        ASSERT_NE(dladdr(p, &info), 0) << symbol;
        EXPECT_NE(std::string(info.dli_fname).find(library), std::string::npos)
            << symbol << " comes from " << info.dli_fname;
    }
}

}  // namespace
