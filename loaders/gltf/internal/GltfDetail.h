// The glTF loader's internal pieces (not installed): raw-byte checks, model validation, conversion to a
// graph, and the names of sgkit's keys in glTF `extras`, shared by the reader and the writer.
#pragma once
#include "loaders/gltf/Gltf.h"
#include "nodes/Group.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>
#include <vector>

namespace sg::gltf {

// Node extras live under this key: {"sgkit": {"kind": "LOD", ...}}.
constexpr const char* kExtrasKey = "sgkit";
// Deeper JSON is rejected before tinygltf parses it (its extras parser recurses once per level).
constexpr int kMaxJsonDepth = 64;
// Deeper node hierarchies are rejected (the conversion recurses once per level).
constexpr int kMaxNodeDepth = 1000;
// A graph whose paths (shared nodes counted once per path, as a Scene's image holds them) exceed this is refused.
constexpr uint64_t kMaxExpandedNodes = uint64_t(1) << 26;
// Accessors without a buffer view (zeros) may not have more elements than this.
constexpr size_t kMaxZeroAccessor = size_t(1) << 24;
// Images larger than this are not decoded (a small file may claim a huge image).
constexpr long long kMaxImagePixels = 1ll << 26;
// EXT_mesh_gpu_instancing instances in one file (each an Instance node of about 170 bytes; a few bytes of
// accessor, or none for an accessor of zeros, must not stand for gigabytes of nodes).
constexpr size_t kMaxInstances = size_t(1) << 21;
constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
constexpr const char* kQuantization = "KHR_mesh_quantization";
constexpr const char* kMeshFeatures = "EXT_mesh_features";
constexpr const char* kStructuralMetadata = "EXT_structural_metadata";
constexpr const char* kInstanceFeatures = "EXT_instance_features";
// Bytes that EXT_meshopt_compression and sparse accessors may expand to in one file: a few bytes of compressed
// data or of sparse values can claim gigabytes.
constexpr size_t kMaxExpandedBytes = size_t(1) << 29;

// Extensions the loader reads: a file that requires another is refused, one that only uses another loads with a
// warning naming it.
bool supportedExtension(const std::string& name);
// Extensions that change only how surfaces are shaded: required, they load with the nearest material sgkit has
// (a warning naming them); any other unsupported required extension refuses the file.
bool shadingOnlyExtension(const std::string& name);

// "nodes[3]"
std::string at(const std::string& array, size_t i);
[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& reason);

// Refuses JSON text nested deeper than kMaxJsonDepth (strings skipped), before a parser that recurses sees it.
void checkJsonDepth(const std::string& file, const unsigned char* data, size_t size);

// Checks on the bytes before tinygltf sees them: a GLB's header and chunk lengths (tinygltf 2.7.0 reads
// up to 8 bytes past a BIN chunk that claims more than the file holds) and the JSON's nesting depth.
void prevalidate(const std::string& file, const unsigned char* data, size_t size, bool binary);

// What tinygltf does not check and the conversion relies on: every index in range, accessors inside their
// buffer views and views inside their buffers, strides, counts and types, finite node matrices, the node
// hierarchy a forest (no cycle, no node with two parents), required extensions supported.
void validate(const std::string& file, const tinygltf::Model& model);
// An accessor type's glTF name ("VEC3"), for messages.
const char* typeName(int type);

// Skins (GltfSkins.cpp, called by validate() before the node checks): node skins and joints that exist, each joint
// in a tree (one parent, no cycle above it), inverse bind matrices of MAT4 floats, one per joint.
void checkSkins(const std::string& file, const tinygltf::Model& model);

// --- JSON that glTF allows and tinygltf 2.7.0 refuses or misreads (GltfNormalize.cpp)

// The type of an accessor whose `type` glTF does not define (a file may hold one it does not use): no
// TINYGLTF_TYPE_ value, and not -1, which the checks use for "no second type".
constexpr int kUnknownType = 0;

// A file rewritten for tinygltf, and what to undo on the model it parses.
struct Normalized {
    std::string bytes;  // the whole file (a GLB with its new JSON chunk)
    // Buffers without data in the file (no uri, other than a GLB's buffer 0 over its BIN chunk:
    // EXT_meshopt_compression's fallback, buffers a file leaves out): given a one-byte data URI (tinygltf refuses
    // them, or hands over a GLB's BIN chunk), emptied after parsing (missingData() then says who needs them).
    std::vector<size_t> absentBuffers;
    std::vector<size_t> unknownTypes;     // accessors of an unknown type: SCALAR for tinygltf, kUnknownType after
    std::vector<size_t> viewlessIndices;  // index accessors without a view (zeros): view 0 for tinygltf
    std::vector<std::string> warnings;
};

// True when a float stands where glTF wants an integer ("mesh": 0.0, which tinygltf silently drops), found by
// reading the JSON text without building it.
bool needsNormalizing(const unsigned char* json, size_t size);
// The file (JSON text or GLB, prevalidated) rewritten as above, and integral floats written as integers; false,
// `out` untouched, when nothing needs it. Throws LoadError naming the path of a non-integral number where glTF
// wants an integer.
bool normalizeForTinygltf(const std::string& file, const unsigned char* data, size_t size, bool binary,
                          Normalized& out);
// The parsed model as the file has it: absent buffers empty, unknown types kUnknownType (not read), index
// accessors without a view.
void undoNormalizing(const Normalized& n, tinygltf::Model& model);

// --- Buffers without data (GltfMissingData.cpp)

// Per accessor: true when it reads a buffer without data (directly or through its sparse views). Such accessors
// are detached (no view, not sparse: zeros to any reader) and views into such buffers emptied, so that nothing
// reads past them; the conversion skips the primitives that use them (Converter::missingData). Call after the
// meshopt decoding has moved its views onto decoded buffers.
std::vector<bool> detachMissingData(tinygltf::Model& model);

// Buffer views compressed with EXT_meshopt_compression (or KHR_meshopt_compression) decoded into buffers of their
// own, before validation; throws LoadError naming bufferViews[i] for data that does not decode.
void decodeMeshopt(const std::string& file, tinygltf::Model& model);

// --- KHR_animation_pointer (GltfAnimations.cpp)

constexpr const char* kAnimationPointer = "KHR_animation_pointer";
// tinygltf 2.7.0 drops an animation channel without target.node, which is how every KHR_animation_pointer channel
// is written. For a file that uses the extension: each animation's channels read again from the JSON (`data` as
// parsed, after prevalidate()), in the file's order, target.node -1 where absent and the pointer kept in
// target_extensions.
void restorePointerChannels(const unsigned char* data, size_t size, bool binary, tinygltf::Model& model);

// --- Sparse accessors (GltfSparse.cpp)

// Checks accessor i's sparse substitution (called by validate() once the buffer views are checked); `denseBytes`
// sums the dense copies so far, held to kMaxExpandedBytes.
void checkSparse(const std::string& file, const tinygltf::Model& model, size_t i, size_t& denseBytes);
// Every sparse accessor of a validated model made dense: a copy of its base (or zeros) with the values
// substituted, in a buffer of its own.
void applySparse(tinygltf::Model& model);

// Element i of an accessor, component by component, as float: normalized integers mapped to [0, 1]
// (unsigned) or [-1, 1] (signed), other integers as their value. Validated accessors only.
struct AccessorReader {
    const unsigned char* base = nullptr;  // null: an accessor without a buffer view reads as zeros
    size_t stride = 0;
    int comp = 0;
    bool normalized = false;

    AccessorReader(const tinygltf::Model& m, const tinygltf::Accessor& a) {
        comp = a.componentType;
        normalized = a.normalized;
        const size_t elem = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(comp))) *
                            size_t(tinygltf::GetNumComponentsInType(uint32_t(a.type)));
        if (a.bufferView == -1) return;
        const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
        base = m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
        stride = v.byteStride ? v.byteStride : elem;
    }
    float component(size_t i, int k) const {
        if (!base) return 0.0f;
        const unsigned char* p = base + i * stride;
        switch (comp) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[k] / 255.0f : float(p[k]);
            case TINYGLTF_COMPONENT_TYPE_BYTE: {  // glTF: max(c / 127, -1)
                const float v = float(int8_t(p[k]));
                return normalized ? std::max(v / 127.0f, -1.0f) : v;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t v;
                std::memcpy(&v, p + 2 * k, 2);
                return normalized ? v / 65535.0f : float(v);
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                int16_t v;
                std::memcpy(&v, p + 2 * k, 2);
                return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
            }
            default: {
                float v;
                std::memcpy(&v, p + 4 * k, 4);
                return v;
            }
        }
    }
    uint32_t index(size_t i) const {
        if (!base) return 0;
        const unsigned char* p = base + i * stride;
        if (comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return *p;
        if (comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
    }
};

// --- EXT_mesh_gpu_instancing (GltfInstancing.cpp)

// A node's EXT_mesh_gpu_instancing object, or null when the node has none.
const tinygltf::Value* instancing(const tinygltf::Node& n);
// How many instances a node's validated extension places (its accessors' common count).
size_t instanceCount(const tinygltf::Model& m, const tinygltf::Node& n);

// Per-instance local matrices (translation * rotation * scale) of node `node`, whose extension validate() has
// checked; throws LoadError naming the attribute and the instance for a value that is not finite, a rotation
// of zero length, or a matrix that cannot place an Instance, or that `world` (the node's) would make infinite.
std::vector<dmat4> instanceMatrices(const std::string& file, const tinygltf::Model& m, int node, const dmat4& world);

// translation * rotation (x y z w, normalized here) * scale: the one composition the reader and the writer use.
dmat4 composeTrs(const dvec3& t, const dvec4& q, const dvec3& s);

// An affine matrix as float translation, rotation quaternion (x y z w) and scale whose composeTrs() gives back
// its upper 3x3 within 1e-6 of its largest column; false when it has a shear or is not affine. The translation
// is m's, rounded to float (how far that moves it is the caller's judgement).
struct FloatTrs {
    vec3 t{0.0f};
    vec4 q{0.0f, 0.0f, 0.0f, 1.0f};
    vec3 s{1.0f};
};
bool splitTrs(const dmat4& m, FloatTrs& out);
// Adds nodes to `into`, in nested Groups of nearby places (a median split of `at`, one point per node) when there
// are more than a few: the cull then passes over a group out of view at once instead of every placement of a
// set that spans a tile.
void addNearbyGrouped(Group& into, const std::vector<ref_ptr<Node>>& nodes, const std::vector<dvec3>& at);

// Reports progress once a load has run for options.progressAfterSeconds, at most ten times a second.
class Progress {
public:
    explicit Progress(const GltfLoadOptions& o) : opt_(o), start_(std::chrono::steady_clock::now()) {}
    void report(double fraction, const char* stage);
    const GltfLoadOptions& options() const { return opt_; }

private:
    const GltfLoadOptions& opt_;
    std::chrono::steady_clock::time_point start_;
    double last_ = -1.0;
};

// Works out Mesh::closed() for every mesh below root (each once) on a loader's thread, so that a page's first draw
// does not (loadGltfPage, the tileset's loads).
void workOutSolids(const Node& root);

// The KHR_lights_punctual light a node carries, if any, placed by the node's world matrix (the light shines down
// its -Z) into `lights`; returns the glTF light's index, or -1 when none was added. A light the renderer cannot use
// (an unknown type, a colour, intensity, range or cone out of the extension's ranges) is a warning naming it, and
// skipped.
int nodeLight(const tinygltf::Model& model, const tinygltf::Node& node, const std::string& nodePath, const dmat4& world,
              std::vector<PunctualLight>& lights, std::vector<std::string>& warnings);

// Builds the graph of the default scene (validated model); per-element problems that do not stop the
// load (points, lines, undecodable images) become warnings.
// `noData` (per accessor, may be empty): what detachMissingData() found.
GltfScene convert(const std::string& file, const tinygltf::Model& model, Progress& progress,
                  std::vector<std::string> warnings, std::vector<bool> noData = {});

}  // namespace sg::gltf
