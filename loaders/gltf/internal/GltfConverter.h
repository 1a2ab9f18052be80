// The conversion of a validated tinygltf model to an sgkit graph: what it has made so far (each material,
// texture, mesh and shared node once) and its parts, each defined in the file of its concern.
#pragma once
#include "loaders/gltf/internal/GltfDetail.h"

#include "nodes/Geometry.h"
#include "nodes/LOD.h"

#include <map>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace sg::gltf {

// --- accessors (GltfAccessors.cpp)

// Float vectors of N components; tightly packed float data is copied in one go.
template <class V, int N>
std::vector<V> readVectors(const tinygltf::Model& m, int acc);
// Unit vectors (xyz; a tangent's w, its handedness, kept): quantized ones come back a little off unit length.
template <class V>
std::vector<V> readUnitVectors(const tinygltf::Model& m, int acc);

// --- extras (GltfExtras.cpp)

// String and finite number members of extras other than sgkit's key.
GltfProperties properties(const tinygltf::Value& extras);
// sgkit's object in extras, or null when there is none.
const tinygltf::Value* sgkitExtras(const tinygltf::Value& extras);

struct Converter {
    using Value = tinygltf::Value;

    Converter(const std::string& f, const tinygltf::Model& model, Progress& p)
        : file(f),
          m(model),
          progress(p),
          materials(model.materials.size()),
          materialDone(model.materials.size()),
          images(model.images.size()),
          imageDone(model.images.size()),
          imageTaken(model.images.size()),
          shared(model.meshes.size()),
          sharedDone(model.meshes.size()) {}

    const std::string& file;
    const tinygltf::Model& m;
    Progress& progress;
    GltfScene out;
    // Made once each, on first use (index: the glTF element).
    std::vector<ref_ptr<Material>> materials;
    std::vector<bool> materialDone;
    // A glTF texture is an image and a sampler: one Texture per image and distinct Sampler value used. Each image is
    // decoded once; its first Texture takes the pixels, any other (the same image under another sampler) a copy.
    std::vector<ref_ptr<Texture>> images;  // per image, null where it does not decode
    std::vector<bool> imageDone, imageTaken;
    std::map<std::pair<int, uint32_t>, ref_ptr<Texture>> textures;  // by image and samplerKey()
    std::map<int, Sampler> samplers;                                // by glTF sampler, converted on first use
    // KHR_texture_transform of classic materials (packers add it to dequantize UVs), by material, and the meshes
    // with it applied to their UVs, by mesh and material.
    std::map<int, mat3> classicUv;
    std::map<std::pair<const Mesh*, int>, ref_ptr<Mesh>> classicUvMeshes;
    // Mode, indices, attributes, and featureKey() with the outline's accessor: primitives with other features or
    // another outline do not share a Mesh.
    std::map<std::tuple<int, int, int, int, int, int, int, int, std::string>, ref_ptr<Mesh>> meshes;
    std::vector<std::vector<ref_ptr<Geometry>>> shared;           // per glTF mesh, one Geometry per primitive
    std::map<const Material*, ref_ptr<Material>> unlitMaterials;  // unlit(): by the material
    std::vector<bool> sharedDone;
    std::map<long long, ref_ptr<Node>> byId;  // sgkit nodes with several parents, by their "id"
    // The node built for each glTF node (its Transform, or the sgkit kind's outer node), by glTF node index; null
    // where none was built. Animation channels and skin joints name nodes through it.
    std::vector<ref_ptr<Node>> nodeOf;
    size_t nodesDone = 0;
    size_t instancesDone = 0;                                // EXT_mesh_gpu_instancing instances, against kMaxInstances
    std::map<int, ref_ptr<Group>> prototypes;                // per glTF mesh of several primitives that is instanced
    std::unordered_map<const Node*, uint64_t> expandedSize;  // nodes below a node, counted per path

    void warn(const std::string& path, const std::string& what) { out.warnings.push_back(path + ": " + what); }

    // --- buffers without data (GltfMissingData.cpp)
    std::vector<bool> noData;  // per accessor: it reads a buffer the file does not hold (detachMissingData)
    // Why primitive p cannot be drawn for want of data (an accessor of its over such a buffer), or empty.
    std::string missingData(const tinygltf::Primitive& p) const;

    // --- extras (GltfExtras.cpp)
    [[noreturn]] void bad(const std::string& path, const std::string& why) { fail(file, path, why); }
    double number(const Value& o, const char* key, const std::string& path, double def);
    std::string string(const Value& o, const char* key, const std::string& path, const std::string& def);
    std::vector<double> numbers(const Value& v, const std::string& path, size_t n);
    float toFloat(double v, const std::string& path);
    dvec3 vec(const Value& o, const char* key, const std::string& path);

    // --- materials and textures (GltfMaterials.cpp)
    // glTF texture t (null when its image does not decode, warned naming `path`, the use).
    ref_ptr<Texture> texture(int t, const std::string& path);
    // Image i decoded, with the default sampler; null (warned) when it does not decode.
    ref_ptr<Texture> image(int i, const std::string& path);
    // glTF sampler i (-1: none, which reads as REPEAT and LINEAR / LINEAR_MIPMAP_LINEAR, as viewers default); a value
    // outside the enum is warned (naming "samplers[i].wrapS" etc.) and the default taken.
    Sampler sampler(int i);
    static uint32_t samplerKey(const Sampler& s) {
        return uint32_t(s.wrapS) | uint32_t(s.wrapT) << 8 | uint32_t(s.magFilter) << 16 | uint32_t(s.minFilter) << 24;
    }
    // KHR_texture_transform of a texture reference: translation * rotation * scale (the extension's matrices),
    // and its texCoord, which overrides the reference's. A value that is not a finite number: a warning, no
    // transform.
    void textureTransform(const tinygltf::ExtensionMap& ext, const std::string& path, TextureSlot& slot);
    // A texture reference of a material: its texture (sRGB or not is the renderer's choice by the use), UV set and
    // transform. A UV set other than 0 and 1 is a warning, and the texture is not used.
    TextureSlot slot(int index, int texCoord, const tinygltf::ExtensionMap& ext, const std::string& path);
    // A material sgkit wrote from a classic one (GltfWrite.cpp) is read back as that: the same look as before it
    // was saved.
    void classic(const Value& x, const std::string& path, Material& mat);
    // A glTF material as a physical one (Material::physical): the metallic-roughness model with its textures,
    // KHR_materials_unlit, KHR_materials_emissive_strength, KHR_texture_transform, alpha modes, double-sidedness.
    ref_ptr<Material> material(int i);
    // Whether the file lists `extension` in extensionsRequired.
    bool requiresExtension(const char* extension) const;
    // A material whose required extension sgkit does not implement, made the nearest it has (a warning names the
    // extension: extensionWarnings): KHR_materials_pbrSpecularGlossiness (diffuse as base colour, metallic 0,
    // roughness 1 - glossiness), WebGL techniques (a diffuse surface of a "diffuse" value's colour or texture).
    void approximate(const tinygltf::Material& gm, const std::string& mp, Material& mat);
    void specularGlossiness(const Value& x, const std::string& path, Material& mat);
    // A colour (3 or 4 numbers) or texture reference ({"index"}) as the base colour or texture.
    void diffuse(const Value& v, const std::string& path, Material& mat);

    // --- accessors (GltfAccessors.cpp)
    // A primitive's indices (its vertices in order when it has none), each checked against the n vertices.
    std::vector<uint32_t> indices(const tinygltf::Primitive& p, size_t n, const std::string& path);

    // --- meshes (GltfMeshes.cpp)
    static void toTriangles(int mode, std::vector<uint32_t>& idx);
    // Primitive `prim` of glTF mesh `gm`, its source and features set.
    ref_ptr<Mesh> mesh(const tinygltf::Primitive& p, const std::string& path, int gm, int prim);
    // A normal map over a mesh without TANGENT: tangents made by MikkTSpace's rules, as glTF asks (once per mesh).
    static void withTangents(Mesh& mesh, const Material* mat);
    // A copy of `mesh` whose UV set `set` has material `mat`'s classicUv applied (once per mesh and material).
    ref_ptr<Mesh> withUvTransform(const ref_ptr<Mesh>& mesh, int mat, int set);
    // One Geometry per drawable primitive of glTF mesh `i`, made once (null for skipped primitives).
    const std::vector<ref_ptr<Geometry>>& geometries(int i);

    // --- points and lines (GltfPointsLines.cpp)
    // LINES, LINE_STRIP or LINE_LOOP indices as segments (pairs; a loop closed back to its first vertex). What
    // makes no whole segment (an odd LINES count, a strip of one vertex) is left out with a warning naming `path`.
    std::vector<uint32_t> toLines(int mode, const std::vector<uint32_t>& idx, const std::string& path);
    // A POINTS or lines primitive's arrays into `mesh`: positions, COLOR_0, and a point's NORMAL. Indexed points
    // become their indexed vertices in index order (`idx`, which indices() has checked).
    void pointsOrLines(const tinygltf::Primitive& p, const std::string& path, std::vector<vec3> positions,
                       const std::vector<uint32_t>& idx, Mesh& mesh);
    // Indexed points' features: each per-vertex value taken at `idx` in order (an implicit set's ids become the
    // vertex indices they stood for).
    static ref_ptr<MeshFeatures> gathered(const MeshFeatures& f, const std::vector<uint32_t>& idx);
    // The _INTENSITY attribute's n values (empty without it), as Mesh::setIntensities() holds them; taken at
    // `order` when given (indexed points).
    std::vector<uint16_t> intensities(const tinygltf::Primitive& p, size_t n, const std::string& path,
                                      const std::vector<uint32_t>* order);
    // A triangle primitive's CESIUM_primitive_outline: its line pairs set on `mesh`, every index checked.
    void outline(const tinygltf::Primitive& p, Mesh& mesh, const std::string& path);
    // The part of a Mesh's key the outline makes: its accessor.
    static std::string outlineKey(const tinygltf::Primitive& p);
    // An unlit copy of `mat` (none stays none), made once: glTF draws points and lines without normals unlit.
    ref_ptr<Material> unlit(const ref_ptr<Material>& mat);

    // --- sgkit's node kinds (GltfNodeKinds.cpp)
    // A relative file name is relative to the directory of the glTF file that names it.
    ref_ptr<Node> pagedLod(const Value& sx, const std::string& xp);
    ref_ptr<Node> makeKind(const std::string& kind, const Value* sx, const std::string& xp, const tinygltf::Node& gn,
                           const dmat4& local, const std::string& path);
    // Child k of nc of an LOD, with its range and error from the LOD's extras (which the caller has checked).
    void addLevel(LOD& lod, ref_ptr<Node> c, const Value& sx, const std::string& xp, size_t k, size_t nc);

    // --- the node tree (GltfConvert.cpp)
    // A warning for each extension not supported: used (ignored), or required and only shading (approximated).
    void extensionWarnings();
    static dmat4 localMatrix(const tinygltf::Node& n);
    // Builds node i and its subtree; null when the node is skipped (with a warning).
    ref_ptr<Node> build(int i, const dmat4& parentWorld);
    // Refuses a node whose world matrix is not finite, naming the field that made it so.
    void checkWorld(const tinygltf::Node& gn, const std::string& path, const dmat4& world);
    // The node's sgkit "id" (-1 when it has none): a node with several parents is built once.
    long long nodeId(const Value* sx, const std::string& xp);
    // The sgkit kind the node is built as ("Transform" for a plain glTF node).
    std::string nodeKind(const tinygltf::Node& gn, const Value* sx, const std::string& xp);
    // The node of `kind`, in a Transform when sgkit's kind has a matrix; an instanced LOD's LOD goes to
    // lodPrototype and a Transform is returned. Null (with a warning) when a matrix cannot be used.
    ref_ptr<Node> makeNode(const std::string& kind, const Value* sx, const std::string& xp, const tinygltf::Node& gn,
                           const dmat4& local, const std::string& path, bool instancedLod, ref_ptr<LOD>& lodPrototype);
    // The node's name, the application's properties in its extras and its sgkit mask, set on the built node.
    void label(Node& inner, const tinygltf::Node& gn, const Value* sx, const std::string& xp);
    // Node i's mesh below `inner`: its instances, its Geometries, or a warning where the kind has no use for it.
    void addMesh(int i, const std::string& kind, const Value* sx, const std::string& xp, Node* inner,
                 const dmat4& world, const std::string& path, bool instancedLod, const ref_ptr<LOD>& lodPrototype);
    // Records how many nodes `node` expands to, refusing a graph that expands to more than kMaxExpandedNodes.
    void countExpanded(const Node* node, const Node* inner, const std::string& kind, const std::string& path);
    uint64_t expanded(const Node* n) const;
    void children(const tinygltf::Node& gn, const std::string& kind, const Value* sx, const std::string& xp,
                  Node* inner, const dmat4& world, const std::string& path);

    // --- EXT_mesh_gpu_instancing (GltfInstancing.cpp)
    // An instanced LOD's one level: the node's mesh, with the one range (and error) its extras give.
    void levelOfInstancedLod(LOD& lod, const tinygltf::Node& gn, const Value& sx, const std::string& xp,
                             const std::string& path);
    // Node i's mesh placed once per instance (the node's own matrix outside them), by Instances of one prototype,
    // the mesh's Geometry (a Group of them for a mesh of several primitives).
    void instances(int i, Group* into, const dmat4& world, const std::string& path, ref_ptr<LOD> lodPrototype);

    // --- EXT_mesh_features, EXT_structural_metadata, EXT_instance_features (GltfMetadata.cpp)
    ref_ptr<PropertyStore> store;  // the file's root EXT_structural_metadata; null without it
    bool externalSchema = false;   // the root extension names its schema by URI: ignored, tables dropped
    // Reads the root EXT_structural_metadata into `store`, before any mesh is made.
    void readMetadata();
    // A node that sgkit wrote as a feature (MetadataWriter::nodeFeature): its binding, over sets shared by every
    // node of the same table, count and label.
    void nodeFeature(Node& inner, const Value& feature, const std::string& path);
    std::map<std::tuple<int, uint32_t, std::string>, ref_ptr<MeshFeatures>> nodeFeatureSets;
    // What primitive p's EXT_mesh_features and EXT_structural_metadata say about its n vertices (or, with
    // GltfLoadOptions::batchTable, its batch ids); null when nothing.
    ref_ptr<MeshFeatures> primitiveFeatures(const tinygltf::Primitive& p, size_t n, const std::string& path);
    // The part of a Mesh's key that the features make: their extensions and the accessors of "_" attributes.
    static std::string featureKey(const tinygltf::Primitive& p);
    // Node i's EXT_instance_features over its n EXT_mesh_gpu_instancing instances; null without it.
    ref_ptr<MeshFeatures> instanceFeatures(int i, size_t n, const std::string& path);

    // --- skins and morph targets (GltfSkins.cpp, GltfMorph.cpp)
    // The part of a Mesh's key its motion makes: the JOINTS_n and WEIGHTS_n accessors, and for morph targets their
    // accessors and the glTF mesh (whose default weights the Mesh holds).
    static std::string motionKey(const tinygltf::Primitive& p, int gm);
    // A primitive's JOINTS_0/1 and WEIGHTS_0/1 into Mesh::setSkinWeights (4 or 8 influences), taken at `order` when
    // given (indexed points); weights that do not sum to one are normalised with a warning.
    void skinWeights(const tinygltf::Primitive& p, Mesh& mesh, const std::string& path,
                     const std::vector<uint32_t>* order);
    // A primitive's morph targets (POSITION, NORMAL, TANGENT displacements) into Mesh::setMorphTargets, glTF mesh
    // gm's weights into Mesh::defaultWeights; taken at `order` when given.
    void morphTargets(const tinygltf::Primitive& p, Mesh& mesh, const std::string& path, int gm,
                      const std::vector<uint32_t>* order);
    // The morph target count of glTF mesh i, refusing primitives of different counts and weights of another length.
    size_t targetCount(int i);
    std::map<int, size_t> targetCounts;  // targetCount()'s, by glTF mesh
    // Bytes of morph target arrays read (a few bytes of JSON can name a large accessor again and again), held to
    // kMaxExpandedBytes; Geometries made for one node alone (nodes x primitives), held to kMaxOwnGeometries.
    size_t targetBytes = 0;
    size_t ownMade = 0;
    static constexpr size_t kMaxOwnGeometries = size_t(1) << 21;
    // The weights node i starts with: its own, else its mesh's; refuses a length other than the target count.
    std::vector<float> startWeights(int i);
    // Node i's own copies of its mesh's Geometries (a skin or morph targets: its weights and skin are its own), with
    // its weights. Unskinned ones go below `inner`; skinned ones wait in `skinned` for skins().
    void ownGeometries(int i, Group& inner, const std::string& path);
    // Skinned Geometries of a node (with their primitive index), placed by skins() once the joints are built.
    struct Skinned {
        int node;
        ref_ptr<Group> inner;  // where they go unskinned; null: an sgkit Geometry node, skinned in its place
        std::vector<std::pair<size_t, ref_ptr<Geometry>>> geometries;
    };
    std::vector<Skinned> skinned;
    // The Geometries made for one glTF node alone, by node index: where its morph weights go (a skinned node's are
    // not below its Transform).
    std::map<int, std::vector<ref_ptr<Geometry>>> nodeGeometries;
    std::map<int, ref_ptr<Skin>> skinsMade;  // by glTF skin; null: a joint was not built
    // Skin s, made once from the nodes built for its joints; null (with a warning) when a joint was not built.
    ref_ptr<Skin> skin(int s);
    // After the node tree: each skinned Geometry given its skin and put under `root` (glTF ignores the skinned
    // node's transform, and a joint may hold that node), named as its node; without a skin, below its node.
    void skins(Group& root);

    // --- animations (GltfAnimations.cpp, GltfAnimationPointer.cpp)
    // The Geometries made with each glTF material, by material index: KHR_animation_pointer's material channels
    // give them changed copies.
    std::map<int, std::vector<ref_ptr<Geometry>>> materialUsers;
    // The entries of out.lights and out.cameras each glTF light and camera became (one per node that carries it).
    std::map<int, std::vector<size_t>> lightEntries, cameraEntries;
    // Every animation of the file into out.animations, bound through nodeOf (after the node tree is built).
    void animations();
    // What a sampler's output accessor may hold: floats only (translation, scale), or also normalized integers
    // (rotation, weights), or also integers taken as their values (KHR_animation_pointer's floats; translation and
    // scale under KHR_mesh_quantization).
    enum class Outputs { Float, Normalized, Integers };
    // One animation as it is read: the sg sampler made from each glTF sampler (-1: none yet) and each one's times.
    struct AnimationRead {
        size_t a;
        const tinygltf::Animation& ga;
        Animation& anim;
        const std::unordered_set<const Node*>& built;  // nodeOf's nodes
        std::vector<int> samplerOf;
        std::vector<std::vector<float>> times;
        std::string path(const char* array, size_t i) const { return at(at("animations", a) + "." + array, i); }
    };
    // glTF sampler s's times, checked: a SCALAR float accessor, strictly increasing.
    void samplerTimes(AnimationRead& r, size_t s);
    size_t animationValues = 0;  // floats read into samplers so far
    // The sg sampler for channel c's glTF sampler, read on first use, its output checked against `type` (an
    // accessor type) and `width` floats a key; `what` names what the channel drives.
    uint32_t channelSampler(AnimationRead& r, size_t c, int type, uint32_t width, Outputs outputs,
                            const std::string& what);
    // A channel driving glTF node `node`'s translation, rotation, scale or weights; `where` names the node in
    // messages. Skipped with a warning when the node was not built.
    void nodeChannel(AnimationRead& r, size_t c, int node, const std::string& path, const std::string& where);
    // A KHR_animation_pointer channel: nodes, material factors, lights, cameras; another pointer is a warning.
    void pointerChannel(AnimationRead& r, size_t c);
    void materialChannel(AnimationRead& r, size_t c, size_t mat, const std::string& property, const std::string& where);
    void lightChannel(AnimationRead& r, size_t c, size_t light, const std::string& property, const std::string& where);
    void cameraChannel(AnimationRead& r, size_t c, size_t cam, const std::string& kind, const std::string& property,
                       const std::string& where);

    // --- cameras (GltfCameras.cpp)
    void camera(int c, const dmat4& world, const std::string& nodeName);
};

}  // namespace sg::gltf
