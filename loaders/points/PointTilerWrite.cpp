// The point tile builder's output: a tile's GLB (through tinygltf) or .pnts, and its entry of tileset.json.
#include "loaders/points/internal/PointTilerDetail.h"

#include <tiny_gltf.h>
#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace sg::pointtiles {
namespace {

template <typename T>
size_t appendBytes(std::vector<unsigned char>& buffer, const std::vector<T>& values) {
    const size_t offset = buffer.size();
    buffer.resize(offset + values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(buffer.data() + offset, values.data(), values.size() * sizeof(T));
    return offset;
}

// One attribute's view and accessor; returns the accessor's index.
int addAttribute(tinygltf::Model& m, size_t offset, size_t length, int stride, int componentType, int type,
                 bool normalized, size_t count) {
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = length;
    view.byteStride = stride;
    view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
    m.bufferViews.push_back(view);
    tinygltf::Accessor a;
    a.bufferView = int(m.bufferViews.size() - 1);
    a.componentType = componentType;
    a.type = type;
    a.normalized = normalized;
    a.count = count;
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
}

// Relative to the centre, in glTF's axes: +Y up, a tileset's +Z turned to +Y (3D Tiles turns it back).
std::vector<float> relativePositions(const dvec3& centre, const std::vector<Point>& points, bool yUp) {
    std::vector<float> xyz;
    xyz.reserve(points.size() * 3);
    for (const Point& p : points) {
        const dvec3 d = p.position - centre;
        xyz.insert(xyz.end(), {float(d.x), float(yUp ? d.z : d.y), float(yUp ? -d.y : d.z)});
    }
    return xyz;
}

}  // namespace

std::string glbBytes(const dvec3& centre, const std::vector<Point>& points, bool intensity) {
    tinygltf::Model m;
    m.asset.version = "2.0";
    m.asset.generator = "sgkit sgtile";
    m.buffers.emplace_back();
    std::vector<unsigned char>& buffer = m.buffers[0].data;
    const size_t n = points.size();

    const std::vector<float> xyz = relativePositions(centre, points, true);
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_POINTS;
    const int pos = addAttribute(m, appendBytes(buffer, xyz), xyz.size() * 4, 12, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                 TINYGLTF_TYPE_VEC3, false, n);
    m.accessors[pos].minValues.assign(3, 0.0);
    m.accessors[pos].maxValues.assign(3, 0.0);
    for (int a = 0; a < 3; ++a) {
        float lo = n ? xyz[a] : 0.0f, hi = lo;
        for (size_t i = 0; i < n; ++i) lo = std::min(lo, xyz[i * 3 + a]), hi = std::max(hi, xyz[i * 3 + a]);
        m.accessors[pos].minValues[a] = lo;
        m.accessors[pos].maxValues[a] = hi;
    }
    prim.attributes["POSITION"] = pos;

    std::vector<uint8_t> rgba(n * 4);
    for (size_t i = 0; i < n; ++i) std::memcpy(&rgba[i * 4], &points[i].color[0], 4);
    prim.attributes["COLOR_0"] = addAttribute(m, appendBytes(buffer, rgba), rgba.size(), 4,
                                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, true, n);
    if (intensity) {
        // A vertex attribute's elements start on four bytes: each uint16 is followed by two bytes of padding.
        std::vector<uint16_t> values(n * 2, 0);
        for (size_t i = 0; i < n; ++i) values[i * 2] = points[i].intensity;
        prim.attributes["_INTENSITY"] =
            addAttribute(m, appendBytes(buffer, values), values.size() * 2, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                         TINYGLTF_TYPE_SCALAR, false, n);
    }
    m.buffers[0].data.resize((buffer.size() + 3) & ~size_t(3), 0);
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(prim);
    m.meshes.push_back(mesh);
    tinygltf::Node node;
    node.mesh = 0;
    node.translation = {centre.x, centre.z, -centre.y};
    m.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    m.scenes.push_back(scene);
    m.defaultScene = 0;

    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&m, out, false, true)) throw std::runtime_error("the GLB cannot be made");
    return out.str();
}

std::string pntsBytes(const dvec3& centre, const std::vector<Point>& points) {
    const size_t n = points.size();
    const std::vector<float> xyz = relativePositions(centre, points, false);
    nlohmann::json table = {{"POINTS_LENGTH", n},
                            {"RTC_CENTER", {centre.x, centre.y, centre.z}},
                            {"POSITION", {{"byteOffset", 0}}},
                            {"RGB", {{"byteOffset", n * 12}}}};
    std::string json = table.dump();
    json.append((8 - (28 + json.size()) % 8) % 8, ' ');  // the binary body starts on eight bytes
    std::string body(n * 15, '\0');
    if (n) std::memcpy(body.data(), xyz.data(), n * 12);
    for (size_t i = 0; i < n; ++i) std::memcpy(&body[n * 12 + i * 3], &points[i].color[0], 3);
    body.append((8 - body.size() % 8) % 8, '\0');
    const uint32_t header[7] = {
        0, 1, uint32_t(28 + json.size() + body.size()), uint32_t(json.size()), uint32_t(body.size()), 0, 0};
    std::string bytes(28, '\0');
    std::memcpy(bytes.data(), header, 28);
    std::memcpy(bytes.data(), "pnts", 4);
    return bytes + json + body;
}

uint64_t writeTile(const std::string& outDir, const Cube& cube, const NodeId& node, const std::vector<Point>& points,
                   bool intensity, bool pnts) {
    const dvec3 centre = node.min(cube) + dvec3(node.edge(cube) * 0.5);
    const std::string file = outDir + "/tiles/" + node.path + (pnts ? ".pnts" : ".glb");
    std::string bytes;
    try {
        bytes = pnts ? pntsBytes(centre, points) : glbBytes(centre, points, intensity);
    } catch (const std::exception& e) {
        throw std::runtime_error(file + ": " + e.what());
    }
    writeFile(file, bytes);
    return bytes.size();
}

std::string openTile(const std::string& path, const TileMeta& meta, double edge, bool pnts, bool root) {
    // Padded: float positions may round past the tight box; a flat scan's box keeps a thickness.
    const dvec3 c = meta.box.center(), h = meta.box.halfExtent() + edge * 1e-6;
    nlohmann::json tile = {{"boundingVolume", {{"box", {c.x, c.y, c.z, h.x, 0, 0, 0, h.y, 0, 0, 0, h.z}}}},
                           {"geometricError", meta.error}};
    if (meta.content) tile["content"] = {{"uri", "tiles/" + path + (pnts ? ".pnts" : ".glb")}};
    if (root) tile["refine"] = "ADD";
    std::string text = tile.dump();
    text.pop_back();  // the closing brace: closeTile() writes it after the children
    return text;
}

std::string closeTile(const std::string& childrenText) {
    return childrenText.empty() ? "}" : ",\"children\":[" + childrenText + "]}";
}

}  // namespace sg::pointtiles
