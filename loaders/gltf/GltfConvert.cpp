// A validated tinygltf model to an sgkit graph: nodes to Transforms (or sgkit's own kinds from `extras`),
// mesh primitives to shared Meshes and Geometries, materials with their base colour texture, cameras.
#include "loaders/gltf/internal/GltfDetail.h"

#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

#include <stb_image.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <map>
#include <tuple>
#include <unordered_map>

namespace sg::gltf {
namespace {

using tinygltf::Value;

// Float vectors of N components; tightly packed float data is copied in one go.
template <class V, int N>
std::vector<V> readVectors(const tinygltf::Model& m, int acc) {
    const tinygltf::Accessor& a = m.accessors[size_t(acc)];
    const AccessorReader r(m, a);
    const int have = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    std::vector<V> out(a.count);
    if (r.base && r.comp == TINYGLTF_COMPONENT_TYPE_FLOAT && have == N && r.stride == sizeof(V)) {
        std::memcpy(out.data(), r.base, a.count * sizeof(V));
        return out;
    }
    for (size_t i = 0; i < a.count; ++i) {
        V v(1.0f);
        for (int k = 0; k < std::min(N, have); ++k) v[k] = r.component(i, k);
        out[i] = v;
    }
    return out;
}

// Unit vectors (xyz; a tangent's w, its handedness, kept): quantized ones come back a little off unit length.
template <class V>
std::vector<V> readUnitVectors(const tinygltf::Model& m, int acc) {
    std::vector<V> out = readVectors<V, V::length()>(m, acc);
    if (m.accessors[size_t(acc)].componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) return out;
    for (V& v : out) {
        const vec3 d(v);
        const float len = glm::length(d);
        if (len > 0.0f) {
            const vec3 u = d / len;
            for (int k = 0; k < 3; ++k) v[k] = u[k];
        }
    }
    return out;
}

// String and finite number members of extras other than sgkit's key.
GltfProperties properties(const Value& extras) {
    GltfProperties p;
    if (!extras.IsObject()) return p;
    for (const std::string& k : extras.Keys()) {
        if (k == kExtrasKey) continue;
        const Value& v = extras.Get(k);
        if (v.IsString())
            p.strings[k] = v.Get<std::string>();
        else if (v.IsNumber() && std::isfinite(v.GetNumberAsDouble()))
            p.numbers[k] = v.GetNumberAsDouble();
    }
    return p;
}

const Value* sgkitExtras(const Value& extras) {
    if (!extras.IsObject() || !extras.Has(kExtrasKey)) return nullptr;
    const Value& v = extras.Get(kExtrasKey);
    return v.IsObject() ? &v : nullptr;
}

struct Converter {
    Converter(const std::string& f, const tinygltf::Model& model, Progress& p)
        : file(f),
          m(model),
          progress(p),
          materials(model.materials.size()),
          materialDone(model.materials.size()),
          textures(model.images.size()),
          textureDone(model.images.size()),
          shared(model.meshes.size()),
          sharedDone(model.meshes.size()) {}

    const std::string& file;
    const tinygltf::Model& m;
    Progress& progress;
    GltfScene out;
    // Made once each, on first use (index: the glTF element).
    std::vector<ref_ptr<Material>> materials;
    std::vector<bool> materialDone;
    std::vector<ref_ptr<Texture>> textures;  // per image
    std::vector<bool> textureDone;
    // KHR_texture_transform of classic materials (packers add it to dequantize UVs), by material, and the meshes
    // with it applied to their UVs, by mesh and material.
    std::map<int, mat3> classicUv;
    std::map<std::pair<const Mesh*, int>, ref_ptr<Mesh>> classicUvMeshes;
    std::map<std::tuple<int, int, int, int, int, int, int, int>, ref_ptr<Mesh>> meshes;  // mode, indices, attributes
    std::vector<std::vector<ref_ptr<Geometry>>> shared;  // per glTF mesh, one Geometry per primitive
    std::vector<bool> sharedDone;
    std::map<long long, ref_ptr<Node>> byId;  // sgkit nodes with several parents, by their "id"
    size_t nodesDone = 0;
    size_t instancesDone = 0;                                // EXT_mesh_gpu_instancing instances, against kMaxInstances
    std::map<int, ref_ptr<Group>> prototypes;                // per glTF mesh of several primitives that is instanced
    std::unordered_map<const Node*, uint64_t> expandedSize;  // nodes below a node, counted per path

    void warn(const std::string& path, const std::string& what) { out.warnings.push_back(path + ": " + what); }

    // --- extras
    [[noreturn]] void bad(const std::string& path, const std::string& why) { fail(file, path, why); }
    double number(const Value& o, const char* key, const std::string& path, double def) {
        if (!o.Has(key)) return def;
        const Value& v = o.Get(key);
        if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) bad(path + "." + key, "must be a finite number");
        return v.GetNumberAsDouble();
    }
    std::string string(const Value& o, const char* key, const std::string& path, const std::string& def) {
        if (!o.Has(key)) return def;
        const Value& v = o.Get(key);
        if (!v.IsString()) bad(path + "." + key, "must be a string");
        return v.Get<std::string>();
    }
    std::vector<double> numbers(const Value& v, const std::string& path, size_t n) {
        if (!v.IsArray() || (n && v.ArrayLen() != n))
            bad(path, n ? "must be an array of " + std::to_string(n) + " numbers" : "must be an array of numbers");
        std::vector<double> r;
        for (size_t i = 0; i < v.ArrayLen(); ++i) {
            const Value& e = v.Get(int(i));
            if (!e.IsNumber() || !std::isfinite(e.GetNumberAsDouble())) bad(at(path, i), "must be a finite number");
            r.push_back(e.GetNumberAsDouble());
        }
        return r;
    }
    float toFloat(double v, const std::string& path) {
        if (!(std::abs(v) <= double(std::numeric_limits<float>::max()))) bad(path, "is out of float range");
        return float(v);
    }
    dvec3 vec(const Value& o, const char* key, const std::string& path) {
        const std::vector<double> v = numbers(o.Get(key), path + "." + key, 3);
        return dvec3(v[0], v[1], v[2]);
    }

    // --- materials and textures
    ref_ptr<Texture> texture(int t, const std::string& path) {
        const int img = m.textures[size_t(t)].source;
        if (img < 0) return {};
        if (textureDone[size_t(img)]) return textures[size_t(img)];
        textureDone[size_t(img)] = true;
        const tinygltf::Image& im = m.images[size_t(img)];
        const unsigned char* bytes = im.image.data();
        size_t size = im.image.size();
        if (im.bufferView != -1) {
            const tinygltf::BufferView& v = m.bufferViews[size_t(im.bufferView)];
            bytes = m.buffers[size_t(v.buffer)].data.data() + v.byteOffset;
            size = v.byteLength;
        }
        const std::string ip = at("images", size_t(img));
        int w = 0, h = 0, n = 0;
        if (!bytes || size == 0 || size > 0x7fffffff || !stbi_info_from_memory(bytes, int(size), &w, &h, &n)) {
            warn(ip, "image cannot be decoded, texture skipped (used by " + path + ")");
            return {};
        }
        if (w <= 0 || h <= 0 || (long long)w * h > kMaxImagePixels) {
            warn(ip,
                 "image of " + std::to_string(w) + " x " + std::to_string(h) + " pixels is too large, texture skipped");
            return {};
        }
        unsigned char* px = stbi_load_from_memory(bytes, int(size), &w, &h, &n, 4);
        if (!px) {
            warn(ip, std::string("image cannot be decoded (") + stbi_failure_reason() + "), texture skipped");
            return {};
        }
        // Rows top to bottom: row 0 is glTF's v = 0, which is also the Renderer's first texture row.
        std::vector<uint8_t> rgba(px, px + size_t(w) * size_t(h) * 4);
        stbi_image_free(px);
        textures[size_t(img)] = make<Texture>(w, h, std::move(rgba));
        return textures[size_t(img)];
    }

    // KHR_texture_transform of a texture reference: translation * rotation * scale (the extension's matrices),
    // and its texCoord, which overrides the reference's. A value that is not a finite number: a warning, no
    // transform.
    void textureTransform(const tinygltf::ExtensionMap& ext, const std::string& path, TextureSlot& slot) {
        const auto it = ext.find("KHR_texture_transform");
        if (it == ext.end() || !it->second.IsObject()) return;
        const Value& t = it->second;
        bool ok = true;
        auto number = [&](const Value& v, double def) {
            const double x = v.IsNumber() ? v.GetNumberAsDouble() : std::nan("");
            ok = ok && std::isfinite(x) && std::abs(x) < 1e30;
            return ok ? x : def;
        };
        auto pair = [&](const char* key, double def) {
            if (!t.Has(key)) return dvec2(def);
            const Value& v = t.Get(key);
            if (!v.IsArray() || v.ArrayLen() != 2) ok = false;
            return ok ? dvec2(number(v.Get(0), def), number(v.Get(1), def)) : dvec2(def);
        };
        const dvec2 o = pair("offset", 0.0), sc = pair("scale", 1.0);
        const double r = t.Has("rotation") ? number(t.Get("rotation"), 0.0) : 0.0;
        if (!ok) {
            warn(path + ".extensions.KHR_texture_transform",
                 "offset, rotation or scale is not a finite number (or an array of the wrong length), ignored");
            return;
        }
        const float c = float(std::cos(r)), s = float(std::sin(r));
        // The extension's rows are [sx c, sy s, ox] and [-sx s, sy c, oy]; glm's constructor takes columns.
        slot.transform = mat3(vec3(float(sc.x) * c, -float(sc.x) * s, 0.0f),
                              vec3(float(sc.y) * s, float(sc.y) * c, 0.0f), vec3(float(o.x), float(o.y), 1.0f));
        if (t.Has("texCoord") && t.Get("texCoord").IsInt()) slot.texCoord = t.Get("texCoord").Get<int>();
    }

    // A texture reference of a material: its texture (sRGB or not is the renderer's choice by the use), UV set and
    // transform. A UV set other than 0 and 1 is a warning, and the texture is not used.
    TextureSlot slot(int index, int texCoord, const tinygltf::ExtensionMap& ext, const std::string& path) {
        TextureSlot t;
        if (index < 0) return t;
        t.texCoord = texCoord;
        textureTransform(ext, path, t);
        if (t.texCoord != 0 && t.texCoord != 1) {
            warn(path, "texCoord " + std::to_string(t.texCoord) + " is not supported (0 and 1 are), texture skipped");
            return TextureSlot{};
        }
        t.texture = texture(index, path);
        return t;
    }

    // A material sgkit wrote from a classic one (GltfWrite.cpp) is read back as that: the same look as before it
    // was saved.
    void classic(const Value& x, const std::string& path, Material& mat) {
        if (string(x, "shading", path, "") != "classic") return;
        mat.physical = false;
        mat.specular = toFloat(number(x, "specular", path, 0.0), path + ".specular");
        mat.shininess = toFloat(number(x, "shininess", path, 32.0), path + ".shininess");
        if (x.Has("bakedLight")) {
            if (!x.Get("bakedLight").IsBool()) bad(path + ".bakedLight", "must be true or false");
            mat.bakedLight = x.Get("bakedLight").Get<bool>();
        }
        mat.doubleSided = true;
    }

    // A glTF material as a physical one (Material::physical): the metallic-roughness model with its textures,
    // KHR_materials_unlit, KHR_materials_emissive_strength, KHR_texture_transform, alpha modes, double-sidedness.
    ref_ptr<Material> material(int i) {
        if (i < 0) return {};
        if (materialDone[size_t(i)]) return materials[size_t(i)];
        materialDone[size_t(i)] = true;
        const tinygltf::Material& gm = m.materials[size_t(i)];
        const auto& pbr = gm.pbrMetallicRoughness;
        const std::string mp = at("materials", size_t(i));
        vec4 c(1.0f);
        for (size_t k = 0; k < 4 && k < pbr.baseColorFactor.size(); ++k) c[int(k)] = float(pbr.baseColorFactor[k]);
        auto mat = make<Material>(c);
        mat->physical = true;
        const TextureSlot base = slot(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                      pbr.baseColorTexture.extensions, mp + ".pbrMetallicRoughness.baseColorTexture");
        mat->texture = base.texture;
        mat->texCoord = base.texCoord;
        mat->textureTransform = base.transform;
        PhysicalMaterial& p = mat->pbr;
        p.metallic = float(pbr.metallicFactor);
        p.roughness = float(pbr.roughnessFactor);
        p.metallicRoughness =
            slot(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                 pbr.metallicRoughnessTexture.extensions, mp + ".pbrMetallicRoughness.metallicRoughnessTexture");
        p.normal =
            slot(gm.normalTexture.index, gm.normalTexture.texCoord, gm.normalTexture.extensions, mp + ".normalTexture");
        p.normalScale = float(gm.normalTexture.scale);
        p.occlusion = slot(gm.occlusionTexture.index, gm.occlusionTexture.texCoord, gm.occlusionTexture.extensions,
                           mp + ".occlusionTexture");
        p.occlusionStrength = float(gm.occlusionTexture.strength);
        p.emissive = slot(gm.emissiveTexture.index, gm.emissiveTexture.texCoord, gm.emissiveTexture.extensions,
                          mp + ".emissiveTexture");
        for (size_t k = 0; k < 3 && k < gm.emissiveFactor.size(); ++k)
            p.emissiveFactor[int(k)] = float(gm.emissiveFactor[k]);
        const auto strength = gm.extensions.find("KHR_materials_emissive_strength");
        if (strength != gm.extensions.end() && strength->second.Has("emissiveStrength")) {
            const Value& v = strength->second.Get("emissiveStrength");
            const double e = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
            if (std::isfinite(e) && e >= 0.0 && e < 1e30)
                p.emissiveFactor *= float(e);
            else
                warn(mp + ".extensions.KHR_materials_emissive_strength.emissiveStrength",
                     "is not a finite number >= 0, ignored");
        }
        mat->unlit = gm.extensions.count("KHR_materials_unlit") != 0;
        mat->doubleSided = gm.doubleSided;
        if (const Value* x = sgkitExtras(gm.extras)) classic(*x, mp + ".extras." + kExtrasKey, *mat);
        // MASK: alpha below the cutoff is cut away, the rest opaque; BLEND: blended, after the opaque items.
        if (gm.alphaMode == "MASK") mat->alphaCutoff = float(gm.alphaCutoff);
        mat->blend = gm.alphaMode == "BLEND";
        if (!mat->physical && mat->textureTransform != mat3(1.0f)) {  // the classic shading has no UV transform
            classicUv[i] = mat->textureTransform;
            mat->textureTransform = mat3(1.0f);
        }
        materials[size_t(i)] = mat;
        return mat;
    }

    // --- meshes
    static void toTriangles(int mode, std::vector<uint32_t>& idx) {
        std::vector<uint32_t> t;
        for (size_t i = 2; i < idx.size(); ++i) {
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                const bool odd = (i % 2) == 1;  // keep the winding of the first triangle
                t.insert(t.end(), {idx[i - 2 + (odd ? 1 : 0)], idx[i - 1 - (odd ? 1 : 0)], idx[i]});
            } else {
                t.insert(t.end(), {idx[0], idx[i - 1], idx[i]});
            }
        }
        idx = std::move(t);
    }

    ref_ptr<Mesh> mesh(const tinygltf::Primitive& p, const std::string& path) {
        auto attr = [&](const char* name) {
            auto it = p.attributes.find(name);
            return it == p.attributes.end() ? -1 : it->second;
        };
        const int pos = attr("POSITION"), nrm = attr("NORMAL"), uv = attr("TEXCOORD_0"), col = attr("COLOR_0"),
                  tan = attr("TANGENT"), uv1 = attr("TEXCOORD_1");
        const auto key = std::make_tuple(p.mode, p.indices, pos, nrm, uv, col, tan, uv1);
        auto found = meshes.find(key);
        if (found != meshes.end()) return found->second;

        std::vector<vec3> positions = readVectors<vec3, 3>(m, pos);
        const size_t n = positions.size();
        std::vector<uint32_t> idx;
        if (p.indices >= 0) {
            const tinygltf::Accessor& a = m.accessors[size_t(p.indices)];
            const AccessorReader r(m, a);
            idx.resize(a.count);
            uint32_t mx = 0;
            if (r.base && r.comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && r.stride == 2) {
                const unsigned char* b = r.base;
                for (size_t i = 0; i < a.count; ++i) {
                    uint16_t v;
                    std::memcpy(&v, b + 2 * i, 2);
                    idx[i] = v;
                    mx = std::max<uint32_t>(mx, v);
                }
            } else {
                for (size_t i = 0; i < a.count; ++i) mx = std::max(mx, idx[i] = r.index(i));
            }
            if (mx >= n) {
                size_t i = 0;
                while (idx[i] < n) ++i;
                bad(path + ".indices", "index " + std::to_string(idx[i]) + " at element " + std::to_string(i) +
                                           " is out of range (" + std::to_string(n) + " vertices)");
            }
        } else {
            idx.resize(n);
            for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
        }
        if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP || p.mode == TINYGLTF_MODE_TRIANGLE_FAN) toTriangles(p.mode, idx);
        auto mesh = make<Mesh>();
        try {
            mesh->set(std::move(positions), nrm >= 0 ? readUnitVectors<vec3>(m, nrm) : std::vector<vec3>{},
                      std::move(idx), uv >= 0 ? readVectors<vec2, 2>(m, uv) : std::vector<vec2>{},
                      col >= 0 ? readVectors<vec4, 4>(m, col) : std::vector<vec4>{});
            mesh->setSurface(tan >= 0 ? readUnitVectors<vec4>(m, tan) : std::vector<vec4>{},
                             uv1 >= 0 ? readVectors<vec2, 2>(m, uv1) : std::vector<vec2>{});
        } catch (const std::exception& e) {
            bad(path, e.what());
        }
        if (!mesh->validBound()) {
            const auto& ps = mesh->positions();
            size_t i = 0;
            while (std::isfinite(ps[i].x) && std::isfinite(ps[i].y) && std::isfinite(ps[i].z)) ++i;
            bad(path + ".attributes.POSITION", "element " + std::to_string(i) + " is not finite (" +
                                                   std::to_string(ps[i].x) + ", " + std::to_string(ps[i].y) + ", " +
                                                   std::to_string(ps[i].z) + ")");
        }
        meshes[key] = mesh;
        return mesh;
    }

    // A normal map over a mesh without TANGENT: tangents made by MikkTSpace's rules, as glTF asks (once per mesh).
    static void withTangents(Mesh& mesh, const Material* mat) {
        if (!mat || !mat->physical || !mat->pbr.normal.texture || !mesh.tangents().empty()) return;
        const int set = mat->pbr.normal.texCoord;
        const size_t n = mesh.positions().size();
        if (mesh.normals().size() != n || (set == 0 ? mesh.uvs() : mesh.uvs1()).size() != n) return;
        mesh.setSurface(generateTangents(mesh, set), mesh.uvs1());
    }

    // A copy of `mesh` whose UV set `set` has material `mat`'s classicUv applied (once per mesh and material).
    ref_ptr<Mesh> withUvTransform(const ref_ptr<Mesh>& mesh, int mat, int set) {
        ref_ptr<Mesh>& out = classicUvMeshes[{mesh.get(), mat}];
        if (out) return out;
        const mat3& t = classicUv[mat];
        std::vector<vec2> uvs = mesh->uvs(), uvs1 = mesh->uvs1();
        for (vec2& uv : set == 0 ? uvs : uvs1) uv = vec2(t * vec3(uv, 1.0f));
        std::vector<uint32_t> idx(mesh->indexCount());
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = mesh->index(i);
        out = make<Mesh>();
        out->set(mesh->positions(), mesh->normals(), std::move(idx), std::move(uvs), mesh->colors());
        out->setSurface(mesh->tangents(), std::move(uvs1));
        return out;
    }

    // One Geometry per drawable primitive of glTF mesh `i`, made once (null for skipped primitives).
    const std::vector<ref_ptr<Geometry>>& geometries(int i) {
        if (sharedDone[size_t(i)]) return shared[size_t(i)];
        sharedDone[size_t(i)] = true;
        auto& gs = shared[size_t(i)];
        const auto& prims = m.meshes[size_t(i)].primitives;
        for (size_t k = 0; k < prims.size(); ++k) {
            const tinygltf::Primitive& p = prims[k];
            const std::string path = at(at("meshes", size_t(i)) + ".primitives", k);
            if (p.mode < TINYGLTF_MODE_TRIANGLES) {
                warn(path, "points and lines are not drawn, primitive skipped");
                gs.push_back({});
            } else if (!p.attributes.count("POSITION")) {
                warn(path, "no POSITION attribute, primitive skipped");
                gs.push_back({});
            } else {
                ref_ptr<Mesh> mh = mesh(p, path);
                ref_ptr<Material> mat = material(p.material);
                if (classicUv.count(p.material)) mh = withUvTransform(mh, p.material, mat->texCoord);
                withTangents(*mh, mat.get());
                gs.push_back(make<Geometry>(std::move(mh), std::move(mat)));
            }
        }
        progress.report(0.6 + 0.4 * double(nodesDone) / double(std::max<size_t>(1, m.nodes.size())), "converting");
        return gs;
    }

    // --- nodes
    static dmat4 localMatrix(const tinygltf::Node& n) {
        if (n.matrix.size() == 16) {
            dmat4 r;
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 4; ++k) r[c][k] = n.matrix[size_t(c * 4 + k)];
            return r;
        }
        dmat4 r(1.0);
        if (n.translation.size() == 3)
            r = glm::translate(r, dvec3(n.translation[0], n.translation[1], n.translation[2]));
        if (n.rotation.size() == 4) {
            const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF: x y z w
            const double len = glm::length(q);
            if (len > 0.0) r = r * glm::mat4_cast(q / len);
        }
        if (n.scale.size() == 3) r = glm::scale(r, dvec3(n.scale[0], n.scale[1], n.scale[2]));
        return r;
    }

    // A relative file name is relative to the directory of the glTF file that names it.
    ref_ptr<Node> pagedLod(const Value& sx, const std::string& xp) {
        auto p = make<PagedLOD>();
        std::string f = string(sx, "file", xp, "");
        if (f.empty()) bad(xp + ".file", "a PagedLOD needs the name of its detail's file");
        const size_t slash = file.find_last_of('/');
        if (f[0] != '/' && slash != std::string::npos) f = file.substr(0, slash + 1) + f;
        p->setFile(f);
        const std::string mode = string(sx, "mode", xp, "distance");
        if (mode != "distance" && mode != "pixelSize") bad(xp + ".mode", "unknown PagedLOD mode '" + mode + "'");
        p->setMode(mode == "distance" ? LOD::Mode::Distance : LOD::Mode::PixelSize);
        const std::string trigger = string(sx, "trigger", xp, "range");
        if (trigger != "range" && trigger != "command")
            bad(xp + ".trigger", "unknown PagedLOD trigger '" + trigger + "'");
        p->setTrigger(trigger == "range" ? PagedLOD::Trigger::Range : PagedLOD::Trigger::Command);
        try {
            p->setRange(toFloat(number(sx, "min", xp, 0.0), xp + ".min"),
                        sx.Has("max") ? toFloat(number(sx, "max", xp, 0.0), xp + ".max") : kInf);
            if (sx.Has("center")) p->setCenter(vec(sx, "center", xp));
            p->setRadius(number(sx, "radius", xp, 0.0));
        } catch (const std::invalid_argument& e) {
            bad(xp, e.what());
        }
        return p;
    }

    ref_ptr<Node> makeKind(const std::string& kind, const Value* sx, const std::string& xp, const tinygltf::Node& gn,
                           const dmat4& local, const std::string& path) {
        if (kind == "Transform") {
            auto t = make<Transform>();
            if (isTranslation(local))
                t->setTranslation(dvec3(local[3]));
            else
                t->setMatrix(local);
            return t;
        }
        if (kind == "Group") return make<Group>();
        if (kind == "LOD") {
            auto lod = make<LOD>();
            const std::string mode = string(*sx, "mode", xp, "distance");
            if (mode != "distance" && mode != "pixelSize") bad(xp + ".mode", "unknown LOD mode '" + mode + "'");
            lod->setMode(mode == "distance" ? LOD::Mode::Distance : LOD::Mode::PixelSize);
            if (sx->Has("center")) lod->setCenter(vec(*sx, "center", xp));
            if (sx->Has("transition")) {
                try {
                    lod->setTransition(toFloat(number(*sx, "transition", xp, 0.0), xp + ".transition"));
                } catch (const std::invalid_argument& e) {
                    bad(xp + ".transition", e.what());
                }
            }
            return lod;
        }
        if (kind == "Switch") return make<Switch>();
        if (kind == "Billboard") {
            auto bb = make<Billboard>();
            const std::string mode = string(*sx, "mode", xp, "axial");
            if (mode != "axial" && mode != "pointEye") bad(xp + ".mode", "unknown Billboard mode '" + mode + "'");
            bb->setMode(mode == "axial" ? Billboard::Mode::Axial : Billboard::Mode::PointEye);
            if (sx->Has("axis")) bb->setAxis(vec(*sx, "axis", xp));
            return bb;
        }
        if (kind == "BspGroup") return make<BspGroup>();
        if (kind == "PagedLOD") return pagedLod(*sx, xp);
        if (kind == "Instance") {
            auto in = make<Instance>();
            in->setMatrix(local);
            return in;
        }
        if (kind == "Occluder") {
            auto oc = make<Occluder>();
            if (sx->Has("polygon")) {
                const Value& pv = sx->Get("polygon");
                if (!pv.IsArray()) bad(xp + ".polygon", "must be an array of points");
                std::vector<dvec3> pts;
                for (size_t i = 0; i < pv.ArrayLen(); ++i) {
                    const std::vector<double> c = numbers(pv.Get(int(i)), at(xp + ".polygon", i), 3);
                    pts.push_back(dvec3(c[0], c[1], c[2]));
                }
                oc->setPolygon(std::move(pts));
            } else {
                Box b;
                b.min = vec(*sx, "min", xp);
                b.max = vec(*sx, "max", xp);
                oc->setBox(b);
            }
            return oc;
        }
        if (kind == "Geometry") {
            if (gn.mesh < 0) {
                auto g = make<Geometry>();
                if (sx->Has("emptyMesh")) g->setMesh(make<Mesh>());
                return g;
            }
            const auto& gs = geometries(gn.mesh);
            if (gs.size() != 1 || !gs[0])
                bad(path + ".mesh", "an sgkit Geometry needs a mesh of one triangle primitive");
            return make<Geometry>(ref_ptr<Mesh>(gs[0]->mesh()), ref_ptr<Material>(gs[0]->material()));
        }
        bad(xp + ".kind", "unknown node kind '" + kind + "'");
    }

    // Builds node i and its subtree; null when the node is skipped (with a warning).
    ref_ptr<Node> build(int i, const dmat4& parentWorld) {
        const tinygltf::Node& gn = m.nodes[size_t(i)];
        const std::string path = at("nodes", size_t(i));
        ++nodesDone;
        const Value* sx = sgkitExtras(gn.extras);
        const std::string xp = path + ".extras." + kExtrasKey;
        const dmat4 local = localMatrix(gn);
        const dmat4 world = parentWorld * local;
        const std::string overflow = nonFiniteElement(world);
        if (!overflow.empty()) {
            const char* field = gn.matrix.size()        ? ".matrix"
                                : gn.scale.size()       ? ".scale"
                                : gn.translation.size() ? ".translation"
                                                        : "";
            bad(path + field, "world matrix is not finite (" + overflow + ")");
        }
        if (gn.camera >= 0) camera(gn.camera, world, gn.name);
        nodeLight(m, gn, path, world, out.lights, out.warnings);
        long long id = -1;
        if (sx && sx->Has("id")) {
            const double v = number(*sx, "id", xp, -1);
            if (v < 0 || v > 9007199254740992.0 || v != std::floor(v))
                bad(xp + ".id", "must be a non-negative integer");
            id = (long long)v;
            auto it = byId.find(id);
            if (it != byId.end()) return it->second;
        }
        std::string kind = sx ? string(*sx, "kind", xp, "Transform") : "Transform";
        // Packers move a mesh to a node of its own (gltfpack: a child with KHR_mesh_quantization's dequantizing
        // transform), leaving an sgkit Geometry without it: read as a Transform over what it became.
        if (kind == "Geometry" && gn.mesh < 0 && !gn.children.empty()) kind = "Transform";
        // An instanced sgkit LOD (saveGltf's): a Transform holds the instances, each of the LOD over the mesh.
        const bool instancedLod = kind == "LOD" && instancing(gn) && gn.mesh >= 0;
        ref_ptr<Node> node;
        ref_ptr<LOD> lodPrototype;
        try {
            node = makeKind(kind, sx, xp, gn, local, path);
            if (instancedLod) {
                lodPrototype = ref_ptr<LOD>(static_cast<LOD*>(node.get()));
                node = makeKind("Transform", nullptr, xp, gn, local, path);
            }
        } catch (const std::invalid_argument& e) {
            if (kind == "Transform") {  // e.g. a zero scale (animations use it to hide things)
                warn(path, std::string("matrix cannot be used (") + e.what() + "), node skipped");
                return {};
            }
            bad(xp, e.what());
        }
        if (kind != "Transform" && kind != "Instance" && !instancedLod && local != dmat4(1.0)) {
            // sgkit writes its kinds without a matrix; one given by hand places the node in a Transform.
            auto t = make<Transform>();
            try {
                t->setMatrix(local);
            } catch (const std::invalid_argument& e) {  // singular, as a plain Transform's above
                warn(path, std::string("matrix cannot be used (") + e.what() + "), node skipped");
                return {};
            }
            t->addChild(node);
            node = t;  // the extras below still apply to the inner node: keep a handle on it
        }
        Node* inner =
            node->kind() == NodeKind::Transform && kind != "Transform" && !instancedLod ? node->child(0) : node.get();
        if (!gn.name.empty()) inner->setName(gn.name);
        if (GltfProperties p = properties(gn.extras); !p.empty()) out.properties[inner] = std::move(p);
        if (sx && sx->Has("mask")) {
            const double mask = number(*sx, "mask", xp, 0);
            if (mask < 0 || mask > 4294967295.0 || mask != std::floor(mask))
                bad(xp + ".mask", "must be a 32-bit unsigned integer");
            inner->setNodeMask(uint32_t(mask));
        }
        const bool instanced = instancing(gn) && gn.mesh >= 0 && (kind == "Transform" || instancedLod);
        if (instancing(gn) && !instanced)
            warn(path + ".extensions." + kInstancing,
                 gn.mesh < 0 ? "needs a mesh to instance, ignored" : "on an sgkit " + kind + " node is ignored");
        if (instanced) {
            if (lodPrototype) levelOfInstancedLod(*lodPrototype, gn, *sx, xp, path);
            instances(i, static_cast<Group*>(inner), world, path, lodPrototype);
        } else if (gn.mesh >= 0 && kind == "Transform") {
            for (const auto& g : geometries(gn.mesh))
                if (g) static_cast<Group*>(inner)->addChild(g);
        } else if (gn.mesh >= 0 && kind != "Geometry") {
            warn(path + ".mesh", "a " + kind + " node's mesh is ignored");
        }
        if (instancedLod && !gn.children.empty())
            bad(path + ".children", "an instanced sgkit LOD has no children: its mesh is its one level");
        if (!instancedLod) children(gn, kind, sx, xp, inner, world, path);
        // Shared nodes make a DAG whose paths a Scene expands: a small file must not stand for a huge scene.
        // (An Instance's prototype has an image of its own, counted where it was built.)
        uint64_t size = 1;
        if (kind != "Instance")
            for (size_t k = 0; k < inner->numChildren(); ++k) size += expanded(inner->child(k));
        if (inner != node.get()) ++size;
        if (size > kMaxExpandedNodes)
            bad(path, "the graph below expands to more than " + std::to_string(kMaxExpandedNodes) +
                          " nodes (shared subgraphs, one entry per path)");
        expandedSize[node.get()] = size;
        if (id >= 0) byId[id] = node;
        return node;
    }
    // EXT_mesh_gpu_instancing: node i's mesh placed once per instance (the node's own matrix outside them), by
    // Instances of one prototype, the mesh's Geometry (a Group of them for a mesh of several primitives).
    // An instanced LOD's one level: the node's mesh, with the one range (and error) its extras give.
    void levelOfInstancedLod(LOD& lod, const tinygltf::Node& gn, const Value& sx, const std::string& xp,
                             const std::string& path) {
        const Value* ranges = sx.Has("ranges") ? &sx.Get("ranges") : nullptr;
        if (!ranges || !ranges->IsArray() || ranges->ArrayLen() != 1)
            bad(xp + ".ranges", "an instanced LOD needs one [min, max] range, its mesh's");
        const auto& gs = geometries(gn.mesh);
        if (gs.size() != 1 || !gs[0])
            bad(path + ".mesh", "an instanced sgkit LOD needs a mesh of one triangle primitive");
        try {
            addLevel(lod, gs[0], sx, xp, 0, 1);
        } catch (const std::invalid_argument& e) {
            bad(xp + ".ranges", e.what());
        }
    }

    // Child k of nc of an LOD, with its range and error from the LOD's extras (which the caller has checked).
    void addLevel(LOD& lod, ref_ptr<Node> c, const Value& sx, const std::string& xp, size_t k, size_t nc) {
        const std::vector<double> r = numbers(sx.Get("ranges").Get(int(k)), at(xp + ".ranges", k), 2);
        lod.addChild(std::move(c), toFloat(r[0], at(xp + ".ranges", k)), toFloat(r[1], at(xp + ".ranges", k)));
        if (!sx.Has("errors")) return;
        const Value& errors = sx.Get("errors");
        if (!errors.IsArray() || errors.ArrayLen() != nc)
            bad(xp + ".errors", "needs one error per child (" + std::to_string(nc) + ")");
        const std::vector<double> e = numbers(errors, xp + ".errors", nc);
        lod.setError(lod.numChildren() - 1, toFloat(e[k], at(xp + ".errors", k)));  // given, 0 included
    }

    void instances(int i, Group* into, const dmat4& world, const std::string& path, ref_ptr<LOD> lodPrototype) {
        const tinygltf::Node& gn = m.nodes[size_t(i)];
        const std::string xp = path + ".extensions." + kInstancing + ".attributes";
        instancesDone += instanceCount(m, gn);
        if (instancesDone > kMaxInstances)
            bad(xp, "the file places more than " + std::to_string(kMaxInstances) + " instances");
        const std::vector<dmat4> placements = instanceMatrices(file, m, i, world);
        std::vector<ref_ptr<Geometry>> drawn;
        for (const auto& g : geometries(gn.mesh))
            if (g) drawn.push_back(g);
        if (drawn.empty()) return;  // every primitive skipped, with a warning each
        ref_ptr<Node> proto = drawn[0];
        if (lodPrototype) {
            proto = lodPrototype;
        } else if (drawn.size() > 1) {
            auto& group = prototypes[gn.mesh];
            if (!group) {
                group = make<Group>();
                for (const auto& g : drawn) group->addChild(g);
            }
            proto = group;
        }
        const std::string scale = instancing(gn)->Get("attributes").Has("SCALE") ? xp + ".SCALE" : xp;
        std::vector<ref_ptr<Node>> placed;
        std::vector<dvec3> where;
        for (size_t k = 0; k < placements.size(); ++k) {
            try {
                placed.push_back(make<Instance>(proto, placements[k]));
                where.push_back(dvec3(placements[k][3]));
            } catch (const std::invalid_argument& e) {  // a singular matrix: rotations are not, so the scale
                bad(scale, "instance " + std::to_string(k) + " cannot be placed (" + e.what() + ")");
            }
        }
        addNearbyGrouped(*into, placed, where);
    }

    uint64_t expanded(const Node* n) const {
        auto it = expandedSize.find(n);
        return it == expandedSize.end() ? 1 : it->second;  // a Geometry shared per glTF mesh
    }

    void children(const tinygltf::Node& gn, const std::string& kind, const Value* sx, const std::string& xp,
                  Node* inner, const dmat4& world, const std::string& path) {
        if (gn.children.empty()) return;
        if (kind == "Geometry" || kind == "Occluder") {
            warn(path + ".children", "a " + kind + " node has no children, they are ignored");
            return;
        }
        if (kind == "Instance") {
            if (gn.children.size() != 1)
                bad(path + ".children", "an sgkit Instance needs exactly one child, its prototype");
            ref_ptr<Node> proto = build(gn.children[0], world);
            try {
                if (proto) static_cast<Instance*>(inner)->setPrototype(proto);
            } catch (const std::invalid_argument& e) {
                bad(path + ".children[0]", e.what());
            }
            return;
        }
        const Value* ranges = kind == "LOD" && sx->Has("ranges") ? &sx->Get("ranges") : nullptr;
        const Value* errors = kind == "LOD" && sx->Has("errors") ? &sx->Get("errors") : nullptr;
        const Value* on = kind == "Switch" && sx->Has("on") ? &sx->Get("on") : nullptr;
        const size_t nc = gn.children.size();
        if (kind == "LOD" && (!ranges || !ranges->IsArray() || ranges->ArrayLen() != nc))
            bad(xp + ".ranges", "needs one [min, max] range per child (" + std::to_string(nc) + ")");
        if (errors && (!errors->IsArray() || errors->ArrayLen() != nc))
            bad(xp + ".errors", "needs one error per child (" + std::to_string(nc) + ")");
        if (on && (!on->IsArray() || on->ArrayLen() != nc))
            bad(xp + ".on", "needs one flag per child (" + std::to_string(nc) + ")");
        auto* group = static_cast<Group*>(inner);
        for (size_t k = 0; k < nc; ++k) {
            ref_ptr<Node> c = build(gn.children[k], world);
            if (!c) continue;
            try {
                if (kind == "LOD") {
                    addLevel(*static_cast<LOD*>(inner), c, *sx, xp, k, nc);
                } else if (kind == "Switch") {
                    const Value& f = on ? on->Get(int(k)) : Value(true);
                    if (!f.IsBool()) bad(at(xp + ".on", k), "must be true or false");
                    static_cast<Switch*>(inner)->addChild(c, f.Get<bool>());
                } else {
                    group->addChild(c);
                }
            } catch (const std::invalid_argument& e) {
                bad(at(path + ".children", k), e.what());
            }
        }
    }

    void camera(int c, const dmat4& world, const std::string& nodeName) {
        const tinygltf::Camera& gc = m.cameras[size_t(c)];
        GltfCamera cam;
        cam.name = gc.name.empty() ? nodeName : gc.name;
        cam.world = world;
        cam.perspective = gc.type == "perspective";
        if (cam.perspective) {
            // Exporters write 0 or degrees now and then: a usable camera, said so, rather than a refused file.
            const double y = gc.perspective.yfov;
            cam.yfovDegrees = glm::degrees(y);
            if (!(std::isfinite(y) && y > 0.0 && y < glm::pi<double>())) {
                cam.yfovDegrees = !std::isfinite(y) ? 60.0 : y <= 0.0 ? 1.0 : 179.0;
                warn(at("cameras", size_t(c)) + ".perspective.yfov",
                     "yfov " + std::to_string(y) + " is not in (0, pi), " + std::to_string(cam.yfovDegrees) +
                         " degrees used");
            }
            cam.aspect = gc.perspective.aspectRatio;
            cam.znear = gc.perspective.znear;
            cam.zfar = gc.perspective.zfar;
        } else {
            cam.xmag = gc.orthographic.xmag;
            cam.ymag = gc.orthographic.ymag;
            cam.znear = gc.orthographic.znear;
            cam.zfar = gc.orthographic.zfar;
        }
        out.cameras.push_back(cam);
    }
};

}  // namespace

GltfScene convert(const std::string& file, const tinygltf::Model& model, Progress& progress,
                  std::vector<std::string> warnings) {
    Converter c(file, model, progress);
    c.out.warnings = std::move(warnings);
    auto root = make<Group>();
    std::vector<int> roots;
    const int scene = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
    if (scene >= 0) {
        roots = model.scenes[size_t(scene)].nodes;
        root->setName(model.scenes[size_t(scene)].name);
        c.out.sceneProperties = properties(model.scenes[size_t(scene)].extras);
    } else {  // no scene: every root node
        std::vector<bool> child(model.nodes.size());
        for (const auto& n : model.nodes)
            for (int k : n.children) child[size_t(k)] = true;
        for (size_t i = 0; i < model.nodes.size(); ++i)
            if (!child[i]) roots.push_back(int(i));
    }
    for (size_t i = 0; i < model.extensionsUsed.size(); ++i)  // required ones validate() has refused
        if (!supportedExtension(model.extensionsUsed[i]))
            c.warn(at("extensionsUsed", i), "extension '" + model.extensionsUsed[i] + "' is not supported, ignored");
    if (!model.animations.empty()) c.warn("animations", "animations are not loaded");
    if (!model.skins.empty()) c.warn("skins", "skins are not loaded (meshes are placed unskinned)");
    progress.report(0.6, "converting");
    for (int r : roots)
        if (ref_ptr<Node> n = c.build(r, dmat4(1.0))) root->addChild(n);
    c.out.root = root;
    progress.report(1.0, "done");
    return std::move(c.out);
}

}  // namespace sg::gltf
