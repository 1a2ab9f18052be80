// saveGltf: an sgkit graph to a tinygltf model (one buffer; meshes, materials and textures stored once;
// sgkit's node kinds in `extras`), written by tinygltf as .glb or .gltf with embedded buffers.
#include "loaders/GltfDetail.h"

#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>

namespace sg {
namespace {

using tinygltf::Value;

Value num(double v) { return Value(v); }
Value vec3v(const dvec3& v) { return Value(Value::Array{num(v.x), num(v.y), num(v.z)}); }

// Application properties beside sgkit's key (which they may not replace).
void addProperties(Value::Object& extras, const GltfProperties& p) {
    for (const auto& [k, v] : p.strings)
        if (k != gltf::kExtrasKey) extras[k] = Value(v);
    for (const auto& [k, v] : p.numbers)
        if (k != gltf::kExtrasKey) extras[k] = Value(v);
}

struct Writer {
    explicit Writer(const GltfSaveOptions& o) : options(o) {}
    const GltfSaveOptions& options;
    tinygltf::Model m;
    std::map<const Mesh*, std::map<std::string, int>> meshAttributes;  // attributes and "indices"
    std::map<std::pair<const Mesh*, const Material*>, int> meshes;
    std::map<const Material*, int> materials;
    std::map<const Texture*, int> textures;
    std::map<const Node*, long long> ids;  // nodes with several parents

    std::vector<unsigned char>& bytes() { return m.buffers[0].data; }

    int view(const void* data, size_t size, int target) {
        auto& b = bytes();
        b.resize((b.size() + 3) & ~size_t(3), 0);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = b.size();
        v.byteLength = size;
        v.target = target;
        b.insert(b.end(), static_cast<const unsigned char*>(data), static_cast<const unsigned char*>(data) + size);
        m.bufferViews.push_back(v);
        return int(m.bufferViews.size() - 1);
    }
    template <class T>
    int accessor(const std::vector<T>& v, int comp, int type, int target) {
        tinygltf::Accessor a;
        a.bufferView = view(v.data(), v.size() * sizeof(T), target);
        a.componentType = comp;
        a.type = type;
        a.count = v.size();
        m.accessors.push_back(a);
        return int(m.accessors.size() - 1);
    }

    const std::map<std::string, int>& attributes(const Mesh& mesh) {
        auto it = meshAttributes.find(&mesh);
        if (it != meshAttributes.end()) return it->second;
        std::map<std::string, int> a;
        a["POSITION"] =
            accessor(mesh.positions(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
        tinygltf::Accessor& pa = m.accessors.back();
        pa.minValues = {mesh.box().min.x, mesh.box().min.y, mesh.box().min.z};
        pa.maxValues = {mesh.box().max.x, mesh.box().max.y, mesh.box().max.z};
        if (!mesh.normals().empty())
            a["NORMAL"] = accessor(mesh.normals(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                   TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!mesh.uvs().empty())
            a["TEXCOORD_0"] =
                accessor(mesh.uvs(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!mesh.colors().empty())
            a["COLOR_0"] = accessor(mesh.colors(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4,
                                    TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!mesh.indices16().empty())
            a["indices"] = accessor(mesh.indices16(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                                    TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        else if (!mesh.indices32().empty())
            a["indices"] = accessor(mesh.indices32(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                    TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        return meshAttributes[&mesh] = std::move(a);
    }

    int texture(const Texture& t) {
        auto it = textures.find(&t);
        if (it != textures.end()) return it->second;
        tinygltf::Image im;
        im.width = t.width();
        im.height = t.height();
        im.component = 4;
        im.bits = 8;
        im.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
        im.image = t.rgba();
        im.mimeType = "image/png";
        m.images.push_back(std::move(im));
        tinygltf::Texture tex;
        tex.source = int(m.images.size() - 1);
        m.textures.push_back(tex);
        return textures[&t] = int(m.textures.size() - 1);
    }

    int material(const Material* mat) {
        if (!mat) return -1;
        auto it = materials.find(mat);
        if (it != materials.end()) return it->second;
        tinygltf::Material gm;
        auto& pbr = gm.pbrMetallicRoughness;
        pbr.baseColorFactor = {mat->baseColor.r, mat->baseColor.g, mat->baseColor.b, mat->baseColor.a};
        pbr.metallicFactor = 0.0;  // sgkit's materials are plain diffuse colours
        pbr.roughnessFactor = 1.0;
        if (mat->texture) pbr.baseColorTexture.index = texture(*mat->texture);
        if (mat->alphaCutoff > 0.0f) {
            gm.alphaMode = "MASK";
            gm.alphaCutoff = double(mat->alphaCutoff);
        }
        if (mat->unlit) {
            gm.extensions["KHR_materials_unlit"] = Value(Value::Object{});
            if (std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), "KHR_materials_unlit") ==
                m.extensionsUsed.end())
                m.extensionsUsed.push_back("KHR_materials_unlit");
        }
        m.materials.push_back(std::move(gm));
        return materials[mat] = int(m.materials.size() - 1);
    }

    int mesh(const Geometry& g) {
        const auto key = std::make_pair<const Mesh*, const Material*>(g.mesh(), g.material());
        auto it = meshes.find(key);
        if (it != meshes.end()) return it->second;
        tinygltf::Primitive p;
        p.mode = TINYGLTF_MODE_TRIANGLES;
        for (const auto& [name, acc] : attributes(*g.mesh())) {
            if (name == "indices")
                p.indices = acc;
            else
                p.attributes[name] = acc;
        }
        p.material = material(g.material());
        tinygltf::Mesh gm;
        gm.primitives.push_back(std::move(p));
        m.meshes.push_back(std::move(gm));
        return meshes[key] = int(m.meshes.size() - 1);
    }

    static void setMatrix(tinygltf::Node& n, const dmat4& mat) {
        if (mat == dmat4(1.0)) return;
        if (isTranslation(mat)) {
            n.translation = {mat[3][0], mat[3][1], mat[3][2]};
            return;
        }
        n.matrix.resize(16);
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) n.matrix[size_t(c * 4 + k)] = mat[c][k];
    }

    // Writes node `n` (and its subtree) as a new glTF node; returns its index.
    int node(const Node& n) {
        const int self = int(m.nodes.size());
        m.nodes.emplace_back();
        tinygltf::Node gn;
        gn.name = n.name();
        Value::Object x;
        if (n.numParents() > 1) {
            auto it = ids.find(&n);
            if (it == ids.end()) it = ids.emplace(&n, (long long)ids.size()).first;
            x["id"] = num(double(it->second));
        }
        if (n.nodeMask() != 0xffffffffu) x["mask"] = num(n.nodeMask());
        switch (n.kind()) {
            case NodeKind::Group: x["kind"] = Value(std::string("Group")); break;
            case NodeKind::Transform: setMatrix(gn, static_cast<const Transform&>(n).matrix()); break;
            case NodeKind::Geometry: {
                x["kind"] = Value(std::string("Geometry"));
                const auto& g = static_cast<const Geometry&>(n);
                // glTF has no empty accessors: a mesh without triangles is written as a flag (its positions
                // and the geometry's material are not kept).
                if (g.mesh() && g.mesh()->indexCount() > 0)
                    gn.mesh = mesh(g);
                else if (g.mesh())
                    x["emptyMesh"] = Value(true);
                break;
            }
            case NodeKind::LOD: {
                const auto& lod = static_cast<const LOD&>(n);
                x["kind"] = Value(std::string("LOD"));
                x["mode"] = Value(std::string(lod.mode() == LOD::Mode::Distance ? "distance" : "pixelSize"));
                if (lod.userCenter()) x["center"] = vec3v(lod.center());
                if (lod.transition() > 0.0f) x["transition"] = num(lod.transition());
                Value::Array ranges, errors;
                for (size_t i = 0; i < lod.numChildren(); ++i) {
                    ranges.push_back(Value(Value::Array{num(lod.range(i).min), num(lod.range(i).max)}));
                    errors.push_back(num(lod.error(i)));
                }
                x["ranges"] = Value(std::move(ranges));
                if (lod.hasErrors()) x["errors"] = Value(std::move(errors));
                break;
            }
            case NodeKind::Switch: {
                const auto& sw = static_cast<const Switch&>(n);
                x["kind"] = Value(std::string("Switch"));
                Value::Array on;
                for (size_t i = 0; i < sw.numChildren(); ++i) on.push_back(Value(sw.isOn(i)));
                x["on"] = Value(std::move(on));
                break;
            }
            case NodeKind::Billboard: {
                const auto& bb = static_cast<const Billboard&>(n);
                x["kind"] = Value(std::string("Billboard"));
                x["mode"] = Value(std::string(bb.mode() == Billboard::Mode::Axial ? "axial" : "pointEye"));
                x["axis"] = vec3v(bb.axis());
                break;
            }
            case NodeKind::Instance:
                x["kind"] = Value(std::string("Instance"));
                setMatrix(gn, static_cast<const Instance&>(n).matrix());
                break;
            case NodeKind::BspGroup: x["kind"] = Value(std::string("BspGroup")); break;
            case NodeKind::PagedLOD: {  // the file, not the detail (the coarse children are written)
                const auto& p = static_cast<const PagedLOD&>(n);
                x["kind"] = Value(std::string("PagedLOD"));
                x["file"] = Value(p.file());
                x["mode"] = Value(std::string(p.mode() == LOD::Mode::Distance ? "distance" : "pixelSize"));
                x["min"] = num(p.rangeMin());
                if (std::isfinite(p.rangeMax())) x["max"] = num(p.rangeMax());
                if (p.userCenter()) x["center"] = vec3v(p.center());
                if (p.radius() > 0.0) x["radius"] = num(p.radius());
                if (p.trigger() == PagedLOD::Trigger::Command) x["trigger"] = Value(std::string("command"));
                break;
            }
            case NodeKind::Occluder: {
                const auto& oc = static_cast<const Occluder&>(n);
                x["kind"] = Value(std::string("Occluder"));
                if (oc.shape() == Occluder::Shape::Polygon) {
                    Value::Array pts;
                    for (const dvec3& p : oc.polygon()) pts.push_back(vec3v(p));
                    x["polygon"] = Value(std::move(pts));
                } else {
                    x["min"] = vec3v(oc.box().min);
                    x["max"] = vec3v(oc.box().max);
                }
                break;
            }
        }
        const Node* detail = n.kind() == NodeKind::PagedLOD ? static_cast<const PagedLOD&>(n).detail() : nullptr;
        for (size_t i = 0; i < n.numChildren(); ++i)
            if (const Node* c = n.child(i); c && c != detail) gn.children.push_back(node(*c));
        Value::Object extras;
        if (options.nodeProperties) addProperties(extras, options.nodeProperties(n));
        if (!x.empty()) extras[gltf::kExtrasKey] = Value(std::move(x));
        if (!extras.empty()) gn.extras = Value(std::move(extras));
        m.nodes[size_t(self)] = std::move(gn);
        return self;
    }
};

}  // namespace

void saveGltf(const Node& root, const std::string& path, const GltfSaveOptions& options) {
    const bool glb = path.size() >= 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
    Writer w(options);
    w.m.asset.version = "2.0";
    w.m.asset.generator = "sgkit";
    w.m.buffers.emplace_back();
    tinygltf::Scene scene;
    // A plain root Group is the scene itself (loadGltf returns the scene as a Group): its children are the roots.
    const bool plainRoot = root.kind() == NodeKind::Group && root.nodeMask() == 0xffffffffu;
    if (plainRoot) {
        scene.name = root.name();
        for (size_t i = 0; i < root.numChildren(); ++i)
            if (const Node* c = root.child(i)) scene.nodes.push_back(w.node(*c));
    } else {
        scene.nodes.push_back(w.node(root));
    }
    if (!options.sceneProperties.empty()) {
        Value::Object extras;
        addProperties(extras, options.sceneProperties);
        scene.extras = Value(std::move(extras));
    }
    w.m.scenes.push_back(std::move(scene));
    w.m.defaultScene = 0;
    if (w.bytes().empty()) w.m.buffers.clear();
    // Written through our own stream: tinygltf's file writer does not report a file it could not open.
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out)
        throw std::runtime_error("saveGltf(): " + path + ": cannot be opened for writing: " + std::strerror(errno));
    tinygltf::TinyGLTF writer;
    bool ok = false;
    try {
        ok = writer.WriteGltfSceneToStream(&w.m, out, !glb, glb);
    } catch (const std::exception& e) {
        throw std::runtime_error("saveGltf(): " + path + ": " + e.what());
    }
    out.close();
    if (!ok || !out) throw std::runtime_error("saveGltf(): " + path + ": cannot be written");
}

}  // namespace sg
