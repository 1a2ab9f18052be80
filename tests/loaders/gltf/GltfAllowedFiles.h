// Small files that glTF 2.0 allows and tinygltf 2.7.0 alone refuses or misreads, each with what loading it must
// give: accessors without a buffer view, an unused accessor of an unknown type, a data URI in a GLB, integers written
// as floats, TRIANGLES counts that are not a multiple of 3, a buffer without data, required extensions that only
// change the shading (and one that changes the geometry, refused).
#pragma once
#include "GltfDoc.h"
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

namespace gltfallowed {

using namespace sg;
using gltftest::bytesOf;
using gltftest::GltfDoc;
using json = nlohmann::json;

constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123;

struct Allowed {
    std::string file;  // its name: what it holds, .gltf or .glb
    std::string bytes;
    std::string warning;           // a substring of one of the warnings; empty: no warning at all
    std::string refusedAt;         // the LoadError's path where the file must be refused; empty: it loads
    bool validatorErrors = false;  // the validator finds errors in it (refused by both)
    std::function<void(const GltfScene&)> check;
};

inline const Geometry* firstGeometry(const Node& n) {
    if (n.kind() == NodeKind::Geometry) return static_cast<const Geometry*>(&n);
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Geometry* g = firstGeometry(*n.child(i))) return g;
    return nullptr;
}

inline std::vector<uint32_t> indicesOf(const Mesh& m) {
    std::vector<uint32_t> out(m.indexCount());
    for (size_t i = 0; i < out.size(); ++i) out[i] = m.index(i);
    return out;
}

inline const std::vector<vec3> kTriangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// POSITION accessors need their bounds (the validator says so).
inline int positions(GltfDoc& d, int view, size_t count) {
    const int a = d.accessor(view, kFloat, count, "VEC3");
    d.j["accessors"][size_t(a)]["min"] = {0, 0, 0};
    d.j["accessors"][size_t(a)]["max"] = {1, 1, 0};
    return a;
}

// One triangle, positions and (when `indexed`) uint16 indices in buffer 0; material 0 when `material`.
inline GltfDoc triangleDoc(bool indexed = true) {
    GltfDoc d(R"([{"attributes": {}}])");
    json& p = d.j["meshes"][0]["primitives"][0];
    p["attributes"]["POSITION"] = positions(d, d.view(bytesOf(kTriangle)), 3);
    if (indexed) p["indices"] = d.accessor(d.view(bytesOf(std::vector<uint16_t>{0, 1, 2})), kUShort, 3, "SCALAR");
    return d;
}

inline void expectTriangle(const GltfScene& s) {
    const Geometry* g = firstGeometry(*s.root);
    ASSERT_NE(g, nullptr);
    ASSERT_NE(g->mesh(), nullptr);
    EXPECT_EQ(g->mesh()->positions(), kTriangle);
    EXPECT_EQ(indicesOf(*g->mesh()), (std::vector<uint32_t>{0, 1, 2}));
}

// (a) Accessors without a buffer view: zeros, then their sparse values (the positions' and the indices').
inline Allowed withoutBufferViews() {
    GltfDoc d(R"([{"attributes": {}}])");
    const int pi = d.view(bytesOf(std::vector<uint16_t>{1, 2}));
    const int pv = d.view(bytesOf(std::vector<vec3>{{1, 0, 0}, {0, 1, 0}}));
    const int ii = d.view(bytesOf(std::vector<uint8_t>{1, 2}));
    const int iv = d.view(bytesOf(std::vector<uint8_t>{1, 2}));
    const int pos = positions(d, -1, 3), idx = d.accessor(-1, kUByte, 3, "SCALAR");
    d.j["accessors"][size_t(pos)]["sparse"] = {
        {"count", 2}, {"indices", {{"bufferView", pi}, {"componentType", kUShort}}}, {"values", {{"bufferView", pv}}}};
    d.j["accessors"][size_t(idx)]["sparse"] = {
        {"count", 2}, {"indices", {{"bufferView", ii}, {"componentType", kUByte}}}, {"values", {{"bufferView", iv}}}};
    d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = pos;
    d.j["meshes"][0]["primitives"][0]["indices"] = idx;
    return {"a_accessors_without_bufferView.gltf", d.text(), "", "", false, expectTriangle};
}

// (b) An accessor of a type glTF does not define, that nothing uses.
inline Allowed unknownType() {
    GltfDoc d = triangleDoc();
    d.accessor(0, kFloat, 1, "VEC5");
    return {"b_unused_accessor_of_unknown_type.gltf",
            d.text(),
            "accessors[2].type: unknown type 'VEC5'",
            "",
            false,
            expectTriangle};
}

// (c) A GLB whose indices are in a second buffer, a data URI (buffer 0 is the BIN chunk).
inline Allowed dataUriInGlb() {
    GltfDoc d(R"([{"attributes": {}}])");
    d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = positions(d, d.view(bytesOf(kTriangle)), 3);
    const std::string idx = bytesOf(std::vector<uint16_t>{0, 1, 2});
    d.j["buffers"].push_back(
        {{"byteLength", idx.size()}, {"uri", "data:application/octet-stream;base64," + gltftest::base64(idx)}});
    d.j["bufferViews"].push_back({{"buffer", 1}, {"byteLength", idx.size()}});
    d.j["meshes"][0]["primitives"][0]["indices"] = d.accessor(1, kUShort, 3, "SCALAR");
    return {"c_data_uri_in.glb", d.glb(), "buffers[1].uri", "", false, expectTriangle};
}

// (d) Integers written as floats (3.0): read as the integers; one with a fraction is refused, naming it.
inline json integersAsFloats() {
    json j = json::parse(triangleDoc().text());
    j["scene"] = 0.0;
    j["scenes"][0]["nodes"][0] = 0.0;
    j["nodes"][0]["mesh"] = 0.0;
    for (json& v : j["bufferViews"]) {
        v["buffer"] = 0.0;
        v["byteLength"] = v["byteLength"].get<double>();
    }
    for (json& a : j["accessors"]) {
        a["bufferView"] = a["bufferView"].get<double>();
        a["componentType"] = a["componentType"].get<double>();
        a["count"] = 3.0;
    }
    json& p = j["meshes"][0]["primitives"][0];
    p["attributes"]["POSITION"] = 0.0;
    p["indices"] = 1.0;
    p["mode"] = 4.0;
    return j;
}
inline Allowed integralFloats() {
    return {"d_integers_as_floats.gltf", integersAsFloats().dump(), "", "", false, expectTriangle};
}
inline Allowed fractionalCount() {
    json j = integersAsFloats();
    j["accessors"][1]["count"] = 2.5;
    return {"d_count_with_a_fraction.gltf", j.dump(), "", "accessors[1].count", true, nullptr};
}

// (e) TRIANGLES of 4 indices, and of 4 vertices: the whole triangle of each is drawn.
inline Allowed partialTriangles() {
    GltfDoc d(R"([{"attributes": {}}, {"attributes": {}}])");
    const std::vector<vec3> quad{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    const int pos = positions(d, d.view(bytesOf(quad)), 4);
    d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = pos;
    d.j["meshes"][0]["primitives"][0]["indices"] =
        d.accessor(d.view(bytesOf(std::vector<uint16_t>{0, 1, 2, 3})), kUShort, 4, "SCALAR");
    d.j["meshes"][0]["primitives"][1]["attributes"]["POSITION"] = pos;
    auto check = [](const GltfScene& s) {
        EXPECT_TRUE(std::any_of(s.warnings.begin(), s.warnings.end(), [](const std::string& w) {
            return w.find("meshes[0].primitives[1]: 4 vertices are not a multiple of 3") != std::string::npos;
        }));
        ASSERT_EQ(s.root->numChildren(), 1u);
        const Node& node = *s.root->child(0);
        ASSERT_EQ(node.numChildren(), 2u);
        for (size_t k = 0; k < 2; ++k)
            EXPECT_EQ(indicesOf(*static_cast<const Geometry*>(node.child(k))->mesh()), (std::vector<uint32_t>{0, 1, 2}))
                << k;
    };
    return {"e_triangles_not_a_multiple_of_3.gltf",
            d.text(),
            "meshes[0].primitives[0]: 4 indices are not a multiple of 3",
            "",
            false,
            check};
}

// (f) A buffer without data (no uri, in a .gltf): the node whose primitive reads it loads without it; its child,
// whose mesh does not, loads whole.
inline Allowed bufferWithoutData() {
    GltfDoc d = triangleDoc(false);
    d.j["buffers"].push_back({{"byteLength", 8}});
    d.j["bufferViews"].push_back({{"buffer", 1}, {"byteLength", 6}});
    json skipped = json::parse(R"({"attributes": {"POSITION": 0}})");
    skipped["indices"] = d.accessor(1, kUShort, 3, "SCALAR");
    json first;
    first["primitives"] = json::array({skipped});
    d.j["meshes"] = json::array({first, d.j["meshes"][0]});
    d.j["nodes"] = json::parse(R"([{"mesh": 0, "children": [1]}, {"mesh": 1}])");
    auto check = [](const GltfScene& s) {
        ASSERT_EQ(s.root->numChildren(), 1u);
        const Node& node = *s.root->child(0);
        ASSERT_EQ(node.numChildren(), 1u);  // the child node; the skipped primitive made no Geometry
        const Geometry* g = firstGeometry(node);
        ASSERT_NE(g, nullptr);
        EXPECT_EQ(g->mesh()->positions(), kTriangle);
    };
    return {"f_buffer_without_data.gltf",
            d.text(),
            "meshes[0].primitives[0]: accessors[1] (indices) has no data",
            "",
            false,
            check};
}

// (g) Required extensions that change only the shading: the nearest material; one that changes the geometry is
// refused, naming it.
inline Allowed requiring(const std::string& file, const char* ext, const json& material,
                         std::function<void(const GltfScene&)> check) {
    GltfDoc d = triangleDoc();
    d.uses(ext, true);
    d.j["materials"] = json::array({material});  // not {material}: compilers differ on what one braced json is
    d.j["meshes"][0]["primitives"][0]["material"] = 0;
    return {file, d.text(), std::string("extensionsRequired[0]: extension '") + ext + "'", "", false, check};
}
inline Allowed specularGlossiness() {
    const json m = {{"extensions",
                     {{"KHR_materials_pbrSpecularGlossiness",
                       {{"diffuseFactor", {0.5, 0.25, 1.0, 1.0}}, {"glossinessFactor", 0.75}}}}}};
    return requiring("g_pbrSpecularGlossiness.gltf", "KHR_materials_pbrSpecularGlossiness", m, [](const GltfScene& s) {
        const Material* mat = firstGeometry(*s.root)->material();
        ASSERT_NE(mat, nullptr);
        EXPECT_EQ(mat->baseColor, vec4(0.5f, 0.25f, 1.0f, 1.0f));
        EXPECT_EQ(mat->pbr.metallic, 0.0f);
        EXPECT_EQ(mat->pbr.roughness, 0.25f);  // 1 - glossiness
    });
}
inline Allowed techniques() {
    const json m = {
        {"extensions",
         {{"KHR_techniques_webgl", {{"technique", 0}, {"values", {{"u_diffuse", {0.5, 0.5, 0.25, 1.0}}}}}}}}};
    return requiring("g_techniques_webgl.gltf", "KHR_techniques_webgl", m, [](const GltfScene& s) {
        const Material* mat = firstGeometry(*s.root)->material();
        ASSERT_NE(mat, nullptr);
        EXPECT_EQ(mat->baseColor, vec4(0.5f, 0.5f, 0.25f, 1.0f));
        EXPECT_EQ(mat->pbr.metallic, 0.0f);
    });
}
inline Allowed clearcoat() {
    const json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.25, 0.5, 0.75, 1.0}}}},
                    {"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}}}}}};
    return requiring("g_clearcoat.gltf", "KHR_materials_clearcoat", m, [](const GltfScene& s) {
        EXPECT_EQ(firstGeometry(*s.root)->material()->baseColor, vec4(0.25f, 0.5f, 0.75f, 1.0f));  // the core part
    });
}
inline Allowed madeUpGeometry() {
    GltfDoc d = triangleDoc();
    d.uses("EXT_made_up_geometry", true);
    return {"g_made_up_geometry.gltf", d.text(), "", "extensionsRequired[0]", false, nullptr};
}

inline std::vector<Allowed> allowedFiles() {
    return {withoutBufferViews(), unknownType(),      dataUriInGlb(),      integralFloats(),
            fractionalCount(),    partialTriangles(), bufferWithoutData(), specularGlossiness(),
            techniques(),         clearcoat(),        madeUpGeometry()};
}

}  // namespace gltfallowed
