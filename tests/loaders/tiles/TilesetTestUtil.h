// The tileset reader's tests' helpers: files written for a test (glb boxes, text, binary subtrees) in a
// directory of its own, and what a cull draws.
#pragma once
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

namespace tilestest {

using namespace sg;
namespace fs = std::filesystem;

// glTF content holding a box (z-up world coordinates min..max), written +Y up as 3D Tiles wants it.
inline void writeBoxGlb(const std::string& path, const dvec3& mn, const dvec3& mx) {
    dmat4 zUpToYUp(1.0);
    zUpToYUp[1] = dvec4(0, 0, -1, 0);  // +Y goes to -Z
    zUpToYUp[2] = dvec4(0, 1, 0, 0);   // +Z goes to +Y
    auto t = make<Transform>(zUpToYUp);
    t->addChild(make<Geometry>(makeBoxMesh(mn, mx), make<Material>()));
    auto root = make<Group>();
    root->addChild(t);
    saveGltf(*root, path);
}

inline void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The text of `path` with its first `from` replaced by `to` (a tileset.json's content URI pointed elsewhere).
inline void replaceInFile(const std::string& path, const std::string& from, const std::string& to) {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from << " is not in " << path;
    text.replace(at, from.size(), to);
    writeText(path, text);
}

struct TempDir {
    std::string path;
    TempDir() {
        path = (fs::temp_directory_path() / ("sgkit-tileset-" + std::to_string(::getpid()) + "-" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name()))
                   .string();
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string operator/(const std::string& f) const { return path + "/" + f; }
};

// A root tile (box over [0, 100]^2 x [0, 10], content root.glb) refined into four quadrant children with contents
// q0..q3.glb, geometric errors 10 and 0. `refine` is the root's.
inline std::string quadTileset(const TempDir& d, const std::string& refine = "REPLACE",
                               const std::string& extraRoot = "") {
    writeBoxGlb(d / "root.glb", dvec3(0, 0, 0), dvec3(100, 100, 5));
    std::string children;
    for (int q = 0; q < 4; ++q) {
        const double x = 25 + 50 * (q % 2), y = 25 + 50 * (q / 2);
        writeBoxGlb(d / ("q" + std::to_string(q) + ".glb"), dvec3(x - 20, y - 20, 0), dvec3(x + 20, y + 20, 10));
        children += std::string(q ? "," : "") + R"({"boundingVolume": {"box": [)" + std::to_string(x) + "," +
                    std::to_string(y) + R"(,5, 25,0,0, 0,25,0, 0,0,5]}, "geometricError": 0, "content": {"uri": "q)" +
                    std::to_string(q) + R"(.glb"}})";
    }
    writeText(d / "tileset.json", R"({"asset": {"version": "1.1"}, "geometricError": 100, "root": {
        "boundingVolume": {"box": [50,50,5, 50,0,0, 0,50,0, 0,0,5]}, "geometricError": 10, "refine": ")" +
                                      refine + R"(", "content": {"uri": "root.glb"}, )" + extraRoot +
                                      R"( "children": [)" + children + "]}}");
    return d / "tileset.json";
}

// The world boxes of what a cull draws from `cam`.
struct Drawn {
    std::multiset<std::pair<long, long>> boxes;  // each item's world bound's min x, min y (rounded)
    CullStats stats;
};
inline Drawn cullOnce(Scene& scene, const Camera& cam, uint64_t frame = 1, double time = -1.0) {
    scene.update(FrameInfo{frame, time < 0.0 ? double(frame) : time});
    CullTraversal cull;
    DrawList list;
    Drawn out;
    CullSettings set;
    cull.cull(scene, cam, set, list, out.stats);
    for (const DrawItem& it : list.items) {
        const dvec3 w = dvec3(dmat4(it.matrix()) * dvec4(it.mesh->box().min, 1.0)) + cam.eye();
        out.boxes.insert({std::lround(w.x), std::lround(w.y)});
    }
    return out;
}

inline Camera lookingDownAt(const dvec3& target, double height) {
    Camera cam;
    cam.setViewport(400, 300);
    cam.setPerspective(60.0, 4.0 / 3.0, 0.5, 1e7);
    cam.setLookAt(target + dvec3(0, -0.01, height), target, dvec3(0, 1, 0));
    return cam;
}

// A binary subtree file: the JSON padded to 8 bytes, then the binary chunk.
inline void writeSubtree(const std::string& path, std::string json, std::vector<unsigned char> bin) {
    while (json.size() % 8) json += ' ';
    while (bin.size() % 8) bin.push_back(0);
    std::vector<unsigned char> out = {'s', 'u', 'b', 't', 1, 0, 0, 0};
    for (uint64_t v : {uint64_t(json.size()), uint64_t(bin.size())})
        for (int i = 0; i < 8; ++i) out.push_back(uint8_t(v >> (8 * i)));
    out.insert(out.end(), json.begin(), json.end());
    out.insert(out.end(), bin.begin(), bin.end());
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(out.data()), long(out.size()));
}

// A tileset of one tile, a 10 m box (box.glb) standing on the origin, written into `dir` as tileset.json.
inline void writeBoxTileset(const std::string& dir) {
    const std::string text = R"({"asset": {"version": "1.1"}, "geometricError": 10, "root": {
    "boundingVolume": {"box": [0,0,5, 5,0,0, 0,5,0, 0,0,5]}, "geometricError": 0, "refine": "REPLACE",
    "content": {"uri": "box.glb"}}})";
    writeText(dir + "/tileset.json", text);
    writeBoxGlb(dir + "/box.glb", sg::dvec3(-5, -5, 0), sg::dvec3(5, 5, 10));
}

// The sg::LoadError `f` throws; a test failure when it throws none.
template <class F>
sg::LoadError errorOf(F f) {
    try {
        f();
    } catch (const sg::LoadError& e) {
        return e;
    }
    ADD_FAILURE() << "nothing was refused";
    return sg::LoadError("", "", "");
}

}  // namespace tilestest
