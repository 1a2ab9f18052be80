// A glTF document built up in JSON by a test, with buffer 0's bytes kept apart: embedded as a data URI (.gltf) or as
// the BIN chunk (.glb). One mesh on one node, whose primitives the test writes; views and accessors appended.
#pragma once
#include "GltfTestUtil.h"
#include "loaders/gltf/Gltf.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace gltftest {

template <class T>
std::string bytesOf(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

struct GltfDoc {
    nlohmann::json j;
    std::string bin;

    // primitives: the mesh's primitives array as JSON.
    explicit GltfDoc(const char* primitives = "[]") {
        j = nlohmann::json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}], "meshes": [{}], "buffers": [{}], "bufferViews": [], "accessors": []})");
        j["meshes"][0]["primitives"] = nlohmann::json::parse(primitives);
    }
    int view(const std::string& bytes, int stride = 0) {
        while (bin.size() % 4) bin.push_back('\0');
        nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
        if (stride) v["byteStride"] = stride;
        bin += bytes;
        j["bufferViews"].push_back(v);
        return int(j["bufferViews"].size()) - 1;
    }
    int accessor(int view, int comp, size_t count, const char* type, bool normalized = false) {
        nlohmann::json a = {{"componentType", comp}, {"count", count}, {"type", type}};
        if (view >= 0) a["bufferView"] = view;
        if (normalized) a["normalized"] = true;
        j["accessors"].push_back(a);
        return int(j["accessors"].size()) - 1;
    }
    void uses(const std::string& ext, bool required) {
        j["extensionsUsed"].push_back(ext);
        if (required) j["extensionsRequired"].push_back(ext);
    }
    std::string text() {
        j["buffers"][0]["byteLength"] = bin.size();
        j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
        return j.dump();
    }
    std::string glb() {
        j["buffers"][0]["byteLength"] = bin.size();
        j["buffers"][0].erase("uri");
        std::string js = j.dump();
        js.append((4 - js.size() % 4) % 4, ' ');
        std::string b = bin;
        b.append((4 - b.size() % 4) % 4, '\0');
        std::string out = "glTF";
        put32(out, 2);
        put32(out, uint32_t(12 + 8 + js.size() + 8 + b.size()));
        put32(out, uint32_t(js.size()));
        put32(out, 0x4E4F534Au);
        out += js;
        put32(out, uint32_t(b.size()));
        put32(out, 0x004E4942u);
        return out + b;
    }
    sg::GltfScene load(bool binary = false) {
        const std::string s = binary ? glb() : text();
        return sg::loadGltfFromMemory(binary ? "doc.glb" : "doc.gltf", s.data(), s.size());
    }
    // The LoadError's JSON path and reason; fails the test when the file loads.
    std::pair<std::string, std::string> refusal(bool binary = false) {
        try {
            load(binary);
        } catch (const sg::LoadError& e) {
            return {e.jsonPath(), e.reason()};
        }
        ADD_FAILURE() << "loaded";
        return {};
    }

private:
    static void put32(std::string& s, uint32_t v) {
        for (int k = 0; k < 4; ++k) s.push_back(char((v >> (8 * k)) & 0xff));
    }
};

}  // namespace gltftest
