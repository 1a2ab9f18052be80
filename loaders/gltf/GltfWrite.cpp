// saveGltf: an sgkit graph to a tinygltf model (one buffer; meshes, materials, textures, images and samplers stored
// once; points and lines as modes 0 and 1, intensities as _INTENSITY, outlines as CESIUM_primitive_outline; sgkit's
// node kinds in `extras`; features through GltfWriteMetadata.cpp, skins, morph targets and animations through
// GltfWriteMotion.cpp), written by tinygltf as .glb or .gltf with embedded buffers.
#include "loaders/gltf/internal/GltfDetail.h"
#include "loaders/gltf/internal/GltfWriteMetadata.h"
#include "loaders/gltf/internal/GltfWriteMotion.h"

#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

#include <stb_image_write.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <tuple>

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
    Writer(const GltfSaveOptions& o, bool binary)
        : options(o),
          glb(binary),
          metadata(
              m, [this](const Texture& t) { return texture(t); }, o.warnings),
          motion(
              m, [this](const void* data, size_t size, int target) { return view(data, size, target); }, o.warnings,
              o.animations) {}
    const GltfSaveOptions& options;
    const bool glb;  // writing a .glb: images go into the binary chunk
    tinygltf::Model m;
    std::map<const Mesh*, std::map<std::string, int>> meshAttributes;      // attributes, "indices" and "outline"
    std::map<std::tuple<const Mesh*, const Material*, bool>, int> meshes;  // by mesh, material, skinned
    std::map<const Material*, int> materials;
    std::map<const Texture*, int> textures;
    std::vector<std::pair<Sampler, int>> samplers;  // the non-default ones written, with their index
    std::map<std::tuple<int, int, size_t>, std::vector<std::pair<const Texture*, int>>>
        imagesByContent;                   // by size, hash
    std::map<const Node*, long long> ids;  // nodes with several parents

    double extent = 0.0;  // the diagonal of the scene's box: float instance translations are held to 1e-6 of it
    std::map<const Node*, Box> bounds;  // subtree boxes in the parent's frame, by node
    bool instanced = false;             // a node with EXT_mesh_gpu_instancing was written
    gltf::MetadataWriter metadata;      // feature ID sets and their property store
    gltf::MotionWriter motion;          // skins, morph targets, animations

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
        if (!mesh.tangents().empty())
            a["TANGENT"] = accessor(mesh.tangents(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4,
                                    TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!mesh.uvs1().empty())
            a["TEXCOORD_1"] =
                accessor(mesh.uvs1(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!mesh.colors().empty()) {
            // glTF's float colours lie in [0, 1]; baked light may round to a hair above 1 (1.0000001).
            std::vector<vec4> c = mesh.colors();
            for (vec4& x : c) x = glm::clamp(x, vec4(0.0f), vec4(1.0f));
            a["COLOR_0"] = accessor(c, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
        }
        if (!mesh.intensities().empty()) {
            // As floats (exact to 2^24): a vertex attribute's elements are 4-byte aligned, and a float needs no
            // padding where a 16-bit value would.
            const std::vector<float> v(mesh.intensities().begin(), mesh.intensities().end());
            a["_INTENSITY"] =
                accessor(v, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ARRAY_BUFFER);
        }
        if (!mesh.indices16().empty())
            a["indices"] = accessor(mesh.indices16(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                                    TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        else if (!mesh.indices32().empty())
            a["indices"] = accessor(mesh.indices32(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                    TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        if (!mesh.outline().empty())  // not bound for drawing as it is: no target
            a["outline"] = accessor(mesh.outline(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 0);
        return meshAttributes[&mesh] = std::move(a);
    }

    // A texture as an image and a sampler: none for the default Sampler (what an absent one reads as), so that files
    // of default textures carry no samplers; one per other distinct Sampler.
    int texture(const Texture& t) {
        auto it = textures.find(&t);
        if (it != textures.end()) return it->second;
        tinygltf::Texture tex;
        tex.source = image(t);
        tex.sampler = sampler(t.sampler);
        m.textures.push_back(tex);
        return textures[&t] = int(m.textures.size() - 1);
    }

    int sampler(const Sampler& s) {
        if (s == Sampler{}) return -1;
        for (const auto& [written, i] : samplers)
            if (written == s) return i;
        // OpenGL's values, as glTF names them; the filters in Sampler's order (magnification: no mipmaps).
        constexpr int kFilter[6] = {9728, 9729, 9984, 9985, 9986, 9987};
        const auto wrap = [](Sampler::Wrap w) {
            return w == Sampler::Wrap::MirroredRepeat ? 33648 : w == Sampler::Wrap::ClampToEdge ? 33071 : 10497;
        };
        const auto filter = [&](Sampler::Filter f) { return size_t(f) < 6 ? kFilter[size_t(f)] : 9987; };
        tinygltf::Sampler gs;
        gs.wrapS = wrap(s.wrapS);
        gs.wrapT = wrap(s.wrapT);
        gs.minFilter = filter(s.minFilter);
        const int mag = filter(s.magFilter);  // a mipmap filter: its filter within a level
        gs.magFilter = mag == 9728 || mag == 9984 || mag == 9986 ? 9728 : 9729;
        m.samplers.push_back(gs);
        samplers.emplace_back(s, int(m.samplers.size() - 1));
        return samplers.back().second;
    }

    // Textures of equal pixels (one image under two samplers, read back as a Texture each) share one image.
    int image(const Texture& t) {
        const std::vector<uint8_t>& px = t.rgba();
        const size_t hash =
            std::hash<std::string_view>()(std::string_view(reinterpret_cast<const char*>(px.data()), px.size()));
        auto& same = imagesByContent[{t.width(), t.height(), hash}];
        for (const auto& [other, i] : same)
            if (other->rgba() == px) return i;
        tinygltf::Image im;
        im.width = t.width();
        im.height = t.height();
        im.component = 4;
        im.bits = 8;
        im.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
        im.mimeType = "image/png";
        if (glb) {
            // In a .glb the PNG goes into the binary chunk (a data URI there is legal but wasteful, and the
            // validator warns about it); tinygltf writes an image with a buffer view and no pixels as it is.
            std::vector<unsigned char> png;
            const auto append = [](void* to, void* data, int size) {
                auto* v = static_cast<std::vector<unsigned char>*>(to);
                v->insert(v->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
            };
            if (!stbi_write_png_to_func(append, &png, t.width(), t.height(), 4, t.rgba().data(), t.width() * 4))
                throw std::runtime_error("saveGltf(): a texture could not be encoded as PNG");
            im.bufferView = view(png.data(), png.size(), 0);
        } else {
            im.image = t.rgba();  // tinygltf encodes it as a PNG data URI
        }
        m.images.push_back(std::move(im));
        same.emplace_back(&t, int(m.images.size() - 1));
        return same.back().second;
    }

    void use(const char* extension) {
        if (std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), extension) == m.extensionsUsed.end())
            m.extensionsUsed.push_back(extension);
    }

    // A texture reference: index, UV set, and the transform as KHR_texture_transform's offset, rotation and scale
    // (a transform the extension made has no shear; one with shear is written without the shear).
    template <class Info>
    void textureInfo(Info& info, const TextureSlot& t) {
        info.index = texture(*t.texture);
        info.texCoord = t.texCoord;
        if (t.transform == mat3(1.0f)) return;
        const mat3& x = t.transform;
        const double sx = glm::length(vec2(x[0])), sy = glm::length(vec2(x[1]));
        const double rotation = std::atan2(-double(x[0].y), double(x[0].x));
        Value::Object tt;
        tt["offset"] = Value(Value::Array{num(x[2].x), num(x[2].y)});
        tt["rotation"] = num(rotation);
        tt["scale"] = Value(Value::Array{num(sx), num(sy)});
        info.extensions["KHR_texture_transform"] = Value(std::move(tt));
        use("KHR_texture_transform");
    }

    // A physical material as glTF's; a classic one as a plain diffuse colour (metallic 0, roughness 1) whose
    // sgkit extras say "classic", so that sgkit reads it back as it was.
    int material(const Material* mat) {
        if (!mat) return -1;
        auto it = materials.find(mat);
        if (it != materials.end()) return it->second;
        tinygltf::Material gm;
        auto& pbr = gm.pbrMetallicRoughness;
        pbr.baseColorFactor = {mat->baseColor.r, mat->baseColor.g, mat->baseColor.b, mat->baseColor.a};
        if (mat->alphaCutoff > 0.0f) {
            gm.alphaMode = "MASK";
            gm.alphaCutoff = double(mat->alphaCutoff);
        } else if (mat->blend) {
            gm.alphaMode = "BLEND";
        }
        gm.doubleSided = mat->doubleSided;
        if (mat->unlit) {
            gm.extensions["KHR_materials_unlit"] = Value(Value::Object{});
            use("KHR_materials_unlit");
        }
        if (mat->physical)
            physical(*mat, gm);
        else
            classic(*mat, gm);
        m.materials.push_back(std::move(gm));
        return materials[mat] = int(m.materials.size() - 1);
    }

    void classic(const Material& mat, tinygltf::Material& gm) {
        gm.pbrMetallicRoughness.metallicFactor = 0.0;
        gm.pbrMetallicRoughness.roughnessFactor = 1.0;
        if (mat.texture) gm.pbrMetallicRoughness.baseColorTexture.index = texture(*mat.texture);
        Value::Object x;
        x["shading"] = Value(std::string("classic"));
        if (mat.specular != 0.0f) {
            x["specular"] = num(mat.specular);
            x["shininess"] = num(mat.shininess);
        }
        if (mat.bakedLight) x["bakedLight"] = Value(true);
        Value::Object extras;
        extras[gltf::kExtrasKey] = Value(std::move(x));
        gm.extras = Value(std::move(extras));
    }

    void physical(const Material& mat, tinygltf::Material& gm) {
        auto& pbr = gm.pbrMetallicRoughness;
        const PhysicalMaterial& p = mat.pbr;
        pbr.metallicFactor = p.metallic;
        pbr.roughnessFactor = p.roughness;
        if (mat.texture)
            textureInfo(pbr.baseColorTexture, TextureSlot{mat.texture, mat.texCoord, mat.textureTransform});
        if (p.metallicRoughness.texture) textureInfo(pbr.metallicRoughnessTexture, p.metallicRoughness);
        if (p.normal.texture) {
            textureInfo(gm.normalTexture, p.normal);
            gm.normalTexture.scale = p.normalScale;
        }
        if (p.occlusion.texture) {
            textureInfo(gm.occlusionTexture, p.occlusion);
            gm.occlusionTexture.strength = p.occlusionStrength;
        }
        if (p.emissive.texture) textureInfo(gm.emissiveTexture, p.emissive);
        // Factors above 1 go out as KHR_materials_emissive_strength (the core factor is limited to [0, 1]).
        const float strength = std::max({p.emissiveFactor.r, p.emissiveFactor.g, p.emissiveFactor.b});
        const vec3 e = strength > 1.0f ? p.emissiveFactor / strength : p.emissiveFactor;
        if (e != vec3(0.0f)) gm.emissiveFactor = {e.r, e.g, e.b};
        if (strength > 1.0f) {
            Value::Object x;
            x["emissiveStrength"] = num(strength);
            gm.extensions["KHR_materials_emissive_strength"] = Value(std::move(x));
            use("KHR_materials_emissive_strength");
        }
    }

    // g's mesh and material as a glTF mesh; `skinned`: with the mesh's JOINTS_n and WEIGHTS_n, for a node with a skin.
    int mesh(const Geometry& g, bool skinned) {
        const auto key = std::make_tuple<const Mesh*, const Material*, bool>(g.mesh(), g.material(), bool(skinned));
        auto it = meshes.find(key);
        if (it != meshes.end()) return it->second;
        tinygltf::Primitive p;
        const Primitive kind = g.mesh()->primitive();
        p.mode = kind == Primitive::Points  ? TINYGLTF_MODE_POINTS
                 : kind == Primitive::Lines ? TINYGLTF_MODE_LINE
                                            : TINYGLTF_MODE_TRIANGLES;
        for (const auto& [name, acc] : attributes(*g.mesh())) {
            if (name == "indices") {
                p.indices = acc;
            } else if (name == "outline") {
                p.extensions["CESIUM_primitive_outline"] = Value(Value::Object{{"indices", Value(acc)}});
                use("CESIUM_primitive_outline");
            } else {
                p.attributes[name] = acc;
            }
        }
        p.material = material(g.material());
        if (const MeshFeatures* f = g.mesh()->features()) metadata.primitive(*f, p);
        if (skinned) motion.skinAttributes(*g.mesh(), p);
        tinygltf::Mesh gm;
        motion.morphTargets(*g.mesh(), p, gm);
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

    // --- EXT_mesh_gpu_instancing

    // The box of n's subtree in its parent's frame (each node once however often it is shared).
    Box bound(const Node& n) {
        auto it = bounds.find(&n);
        if (it != bounds.end()) return it->second;
        Box b;
        if (n.kind() == NodeKind::Geometry) {
            const Mesh* mesh = static_cast<const Geometry&>(n).mesh();
            if (mesh && mesh->primitiveCount() > 0) b = mesh->box();
        } else if (n.kind() != NodeKind::Occluder) {  // occluders are not drawn
            for (size_t i = 0; i < n.numChildren(); ++i)
                if (const Node* c = n.child(i)) b.expand(bound(*c));
            const dmat4 mat = n.kind() == NodeKind::Transform  ? static_cast<const Transform&>(n).matrix()
                              : n.kind() == NodeKind::Instance ? static_cast<const Instance&>(n).matrix()
                                                               : dmat4(1.0);
            if (!b.empty() && mat != dmat4(1.0)) b = transformBox(mat, b);
        }
        return bounds[&n] = b;
    }

    // Nothing of the node but its kind and matrix would be lost by not writing it as a node of its own.
    bool plain(const Node& n) const {
        return n.name().empty() && n.nodeMask() == 0xffffffffu &&
               (!options.nodeProperties || options.nodeProperties(n).empty());
    }

    // Instances of one Geometry under one parent, each placement as float translation, rotation and scale;
    // or of one LOD whose one level is that Geometry (an instanced sgkit LOD: each placement switches alone).
    struct Batch {
        const Geometry* geometry = nullptr;
        const LOD* lod = nullptr;
        std::vector<const Node*> members;
        std::vector<gltf::FloatTrs> placements;
    };

    // The batches among n's children (world: their parent frame's world matrix), two instances or more each.
    std::vector<Batch> batches(const Node& n, const dmat4& world) {
        std::vector<Batch> found;
        if (!options.gpuInstancing || (n.kind() != NodeKind::Group && n.kind() != NodeKind::Transform)) return found;
        std::map<const Node*, size_t> byPrototype;
        for (size_t i = 0; i < n.numChildren(); ++i) {
            const Node* c = n.child(i);
            if (!c || c->kind() != NodeKind::Instance || c->numParents() != 1 || !plain(*c)) continue;
            const auto& in = static_cast<const Instance&>(*c);
            const Node* proto = in.prototype();
            dmat4 placement = in.matrix();
            if (proto && proto->kind() == NodeKind::Transform && proto->numChildren() == 1 && plain(*proto)) {
                placement = placement * static_cast<const Transform*>(proto)->matrix();  // folded into each
                proto = proto->child(0);
            }
            const LOD* lod = nullptr;
            if (proto && proto->kind() == NodeKind::LOD && proto->numChildren() == 1 && plain(*proto)) {
                lod = static_cast<const LOD*>(proto);
                proto = proto->child(0);
            }
            if (!proto || proto->kind() != NodeKind::Geometry || !plain(*proto)) continue;
            const auto* g = static_cast<const Geometry*>(proto);
            if (!g->mesh() || g->mesh()->primitiveCount() == 0) continue;
            // What an animation or a skin names stays a node of its own.
            if (motion.pinned(*c) || motion.pinned(*in.prototype()) || motion.pinned(*g) ||
                (lod && motion.pinned(*lod)))
                continue;
            gltf::FloatTrs trs;
            if (!gltf::splitTrs(placement, trs)) continue;  // a shear: the Instance is written as it is
            // The float translation must not move the instance by more than 1e-6 of the scene, as drawn.
            const double moved = glm::length(dvec3(trs.t) - dvec3(placement[3])) * maxScale(world);
            if (!(moved <= 1e-6 * extent)) continue;
            auto [it, fresh] = byPrototype.emplace(in.prototype(), found.size());
            if (fresh) found.push_back({g, lod, {}, {}});
            found[it->second].members.push_back(c);
            found[it->second].placements.push_back(trs);
        }
        found.erase(std::remove_if(found.begin(), found.end(), [](const Batch& b) { return b.members.size() < 2; }),
                    found.end());
        return found;
    }

    // Gives gn the batch's mesh and its instances (rotation and scale only where some instance has them).
    void instancing(tinygltf::Node& gn, const Batch& b) {
        gn.mesh = mesh(*b.geometry, false);
        std::vector<vec3> t, s;
        std::vector<vec4> q;
        bool rotated = false, scaled = false;
        for (const gltf::FloatTrs& p : b.placements) {
            t.push_back(p.t);
            q.push_back(p.q);
            s.push_back(p.s);
            rotated |= p.q != vec4(0.0f, 0.0f, 0.0f, 1.0f);
            scaled |= p.s != vec3(1.0f);
        }
        Value::Object attributes;
        attributes["TRANSLATION"] = Value(accessor(t, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 0));
        if (rotated) attributes["ROTATION"] = Value(accessor(q, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 0));
        if (scaled) attributes["SCALE"] = Value(accessor(s, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 0));
        metadata.instances(b.members, attributes, gn);
        gn.extensions[gltf::kInstancing] = Value(Value::Object{{"attributes", Value(std::move(attributes))}});
        instanced = true;
    }

    int batchNode(const Batch& b) {
        tinygltf::Node gn;
        instancing(gn, b);
        if (b.lod) {
            Value::Object x;
            lodExtras(*b.lod, x);
            gn.extras = Value(Value::Object{{gltf::kExtrasKey, Value(std::move(x))}});
        }
        m.nodes.push_back(std::move(gn));
        return int(m.nodes.size() - 1);
    }

    static void lodExtras(const LOD& lod, Value::Object& x) {
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
    }

    // A PagedLOD's settings: the file, not the detail (the coarse children are written).
    static void pagedLodExtras(const PagedLOD& p, Value::Object& x) {
        x["kind"] = Value(std::string("PagedLOD"));
        x["file"] = Value(p.file());
        x["mode"] = Value(std::string(p.mode() == LOD::Mode::Distance ? "distance" : "pixelSize"));
        x["min"] = num(p.rangeMin());
        if (std::isfinite(p.rangeMax())) x["max"] = num(p.rangeMax());
        if (p.userCenter()) x["center"] = vec3v(p.center());
        if (p.radius() > 0.0) x["radius"] = num(p.radius());
        if (p.trigger() == PagedLOD::Trigger::Command) x["trigger"] = Value(std::string("command"));
    }

    static void occluderExtras(const Occluder& oc, Value::Object& x) {
        x["kind"] = Value(std::string("Occluder"));
        if (oc.shape() == Occluder::Shape::Polygon) {
            Value::Array pts;
            for (const dvec3& p : oc.polygon()) pts.push_back(vec3v(p));
            x["polygon"] = Value(std::move(pts));
        } else {
            x["min"] = vec3v(oc.box().min);
            x["max"] = vec3v(oc.box().max);
        }
    }

    // What n's kind puts in gn: its matrix or mesh, and its settings in sgkit's extras `x`.
    void kindExtras(const Node& n, tinygltf::Node& gn, Value::Object& x) {
        switch (n.kind()) {
            case NodeKind::Group: x["kind"] = Value(std::string("Group")); break;
            case NodeKind::Transform:
                if (!motion.trs(static_cast<const Transform&>(n), gn))
                    setMatrix(gn, static_cast<const Transform&>(n).matrix());
                break;
            case NodeKind::Geometry: {
                x["kind"] = Value(std::string("Geometry"));
                const auto& g = static_cast<const Geometry&>(n);
                // glTF has no empty accessors: a mesh that draws nothing is written as a flag (its positions
                // and the geometry's material are not kept).
                // A skinned one's mesh is given once its skin is known (MotionWriter::finish).
                if (g.mesh() && g.mesh()->primitiveCount() > 0 && !g.skin())
                    gn.mesh = mesh(g, false);
                else if (g.mesh() && g.mesh()->primitiveCount() == 0)
                    x["emptyMesh"] = Value(true);
                gltf::MotionWriter::nodeWeights(g, gn);
                break;
            }
            case NodeKind::LOD: lodExtras(static_cast<const LOD&>(n), x); break;
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
            case NodeKind::PagedLOD: pagedLodExtras(static_cast<const PagedLOD&>(n), x); break;
            case NodeKind::Occluder: occluderExtras(static_cast<const Occluder&>(n), x); break;
        }
    }

    // Writes node `n` (and its subtree) as a new glTF node; returns its index. world: n's parent's world matrix.
    int node(const Node& n, const dmat4& world) {
        const int self = int(m.nodes.size());
        m.nodes.emplace_back();
        motion.written(n, self);
        tinygltf::Node gn;
        gn.name = n.name();
        Value::Object x;
        if (n.numParents() > 1) {
            auto it = ids.find(&n);
            if (it == ids.end()) it = ids.emplace(&n, (long long)ids.size()).first;
            x["id"] = num(double(it->second));
        }
        if (n.nodeMask() != 0xffffffffu) x["mask"] = num(n.nodeMask());
        if (Value f = metadata.nodeFeature(n); f.IsObject()) x["feature"] = std::move(f);
        kindExtras(n, gn, x);
        const Node* detail = n.kind() == NodeKind::PagedLOD ? static_cast<const PagedLOD&>(n).detail() : nullptr;
        const dmat4 inner = n.kind() == NodeKind::Transform  ? world * static_cast<const Transform&>(n).matrix()
                            : n.kind() == NodeKind::Instance ? world * static_cast<const Instance&>(n).matrix()
                                                             : world;
        const std::vector<Batch> bs = batches(n, inner);
        std::set<const Node*> batched;
        for (size_t k = 0; k < bs.size(); ++k) {
            batched.insert(bs[k].members.begin(), bs[k].members.end());
            if (k == 0 && n.kind() == NodeKind::Transform && !bs[k].lod)  // room for one mesh, not an LOD
                instancing(gn, bs[k]);
            else
                gn.children.push_back(batchNode(bs[k]));
        }
        for (size_t i = 0; i < n.numChildren(); ++i)
            if (const Node* c = n.child(i); c && c != detail && !batched.count(c))
                gn.children.push_back(node(*c, inner));
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
    Writer w(options, glb);
    w.m.asset.version = "2.0";
    w.m.asset.generator = "sgkit";
    w.m.buffers.emplace_back();
    tinygltf::Scene scene;
    // A plain root Group is the scene itself (loadGltf returns the scene as a Group): its children are the roots.
    const Box box = w.bound(root);
    w.extent = box.empty() ? 0.0 : glm::length(box.max - box.min);
    const bool plainRoot = root.kind() == NodeKind::Group && root.nodeMask() == 0xffffffffu;
    if (plainRoot) {
        scene.name = root.name();
        std::set<const Node*> batched;
        for (const Writer::Batch& b : w.batches(root, dmat4(1.0))) {
            batched.insert(b.members.begin(), b.members.end());
            scene.nodes.push_back(w.batchNode(b));
        }
        for (size_t i = 0; i < root.numChildren(); ++i)
            if (const Node* c = root.child(i); c && !batched.count(c)) scene.nodes.push_back(w.node(*c, dmat4(1.0)));
    } else {
        scene.nodes.push_back(w.node(root, dmat4(1.0)));
    }
    if (w.instanced) {  // as gltfpack does: without it a reader would draw the mesh once, in the wrong place
        w.m.extensionsUsed.push_back(gltf::kInstancing);
        w.m.extensionsRequired.push_back(gltf::kInstancing);
    }
    w.motion.finish([&w](const Geometry& g, bool skinned) { return w.mesh(g, skinned); });
    w.metadata.finish();
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
        if (w.motion.pointers()) {  // written to memory first: KHR_animation_pointer channels need a fix
            std::ostringstream text;
            ok = writer.WriteGltfSceneToStream(&w.m, text, !glb, glb);
            const std::string fixed = gltf::withoutPointerNodes(text.str(), glb);
            out.write(fixed.data(), std::streamsize(fixed.size()));
        } else {
            ok = writer.WriteGltfSceneToStream(&w.m, out, !glb, glb);
        }
    } catch (const std::exception& e) {
        throw std::runtime_error("saveGltf(): " + path + ": " + e.what());
    }
    out.close();
    if (!ok || !out) throw std::runtime_error("saveGltf(): " + path + ": cannot be written");
}

}  // namespace sg
