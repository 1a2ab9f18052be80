// glTF 2.0 in and out (.gltf with external or embedded buffers, .glb), through tinygltf, with the
// validation tinygltf does not do. sgkit's own node kinds travel in glTF `extras`.
#pragma once
#include "sg/build/GeneratedOccluders.h"
#include "sg/core/Animation.h"
#include "sg/core/DirectionalLight.h"
#include "sg/core/Math.h"
#include "sg/core/Node.h"
#include "sg/core/Properties.h"

#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace sg {

// A file that cannot be loaded: names the file, the JSON path of the offending element (for example
// "meshes[2].primitives[0].indices", empty when the file as a whole is bad) and the reason.
class LoadError : public std::runtime_error {
public:
    LoadError(std::string file, std::string jsonPath, std::string reason);
    const std::string& file() const { return file_; }
    const std::string& jsonPath() const { return path_; }
    const std::string& reason() const { return reason_; }

private:
    std::string file_, path_, reason_;
};

struct GltfCamera {
    std::string name;
    dmat4 world{1.0};  // the camera node's world matrix (the camera looks down its -Z)
    bool perspective = true;
    double yfovDegrees = 60.0, aspect = 0.0, znear = 0.1, zfar = 0.0;  // aspect/zfar 0: not given
    double xmag = 1.0, ymag = 1.0;                                     // orthographic half sizes
};

struct GltfLoadOptions {
    // Called now and then during a load that has taken over a second: fraction done in [0, 1] and the stage.
    std::function<void(double fraction, const std::string& stage)> progress;
    // How long a load runs before `progress` is first called (tests set 0 to see every report).
    double progressAfterSeconds = 1.0;
    // Occluders made from the file's geometry (sg::generateOccluders, sg/build/GeneratedOccluders.h) for the
    // occlusion pass: a file with sgkit's own authored occluders keeps them where they are.
    bool generateOccluders = false;
    OccluderGenSettings occluders;
    // A 3D Tiles 1.0 tile's batch table as a store (table 0): a primitive with a _BATCHID (or BATCH_ID) attribute
    // and no EXT_mesh_features gets a feature ID set of those ids over table 0 of it.
    ref_ptr<const PropertyStore> batchTable;
};

// An application's data in a glTF node's or scene's `extras`, beside sgkit's own key: strings and numbers by
// name (a map region's id, name and area). Other JSON values in extras are not read.
struct GltfProperties {
    std::map<std::string, std::string> strings;
    std::map<std::string, double> numbers;
    bool empty() const { return strings.empty() && numbers.empty(); }
};

struct GltfSaveOptions {
    // Called for each node written: what to put in its extras (nothing when empty).
    std::function<GltfProperties(const Node&)> nodeProperties;
    GltfProperties sceneProperties;  // the scene's extras
    // Two or more Instances under one Group or Transform, of one Geometry (or a Transform over one, or an LOD
    // of that one level), whose matrices are translation * rotation * scale in float go out as one node with
    // EXT_mesh_gpu_instancing; an LOD's in the node's sgkit extras (other readers draw the level everywhere).
    bool gpuInstancing = true;
    // What was left out (feature properties of a second property store: a glTF file holds one), each naming the
    // part; null: not reported.
    std::vector<std::string>* warnings = nullptr;
    // The animations to write (glTF animations over the written nodes): a channel whose node is not written is left
    // out with a warning in `warnings`.
    std::vector<ref_ptr<Animation>> animations;
};

struct GltfScene {
    ref_ptr<Node> root;  // a Group holding the default scene's root nodes
    std::vector<GltfCamera> cameras;
    // KHR_lights_punctual lights of the default scene's nodes, in world axes (glTF's +Y up: a renderer showing
    // them as they are meant sets DirectionalLight::up to +Y).
    std::vector<PunctualLight> lights;
    // Properties found in node extras, by the node built from that glTF node; the scene's in sceneProperties.
    std::unordered_map<const Node*, GltfProperties> properties;
    GltfProperties sceneProperties;
    std::vector<std::string> warnings;  // what was skipped or converted, each naming its JSON path
    // The file's animations, in its order, bound to the nodes built here (a Viewer plays them:
    // viewer.animations().add(a)). KHR_animation_pointer channels replace the Geometries' materials with changed
    // copies, and write lights and cameras into these (shared with the channels' setters: copies of `lights` and
    // `cameras` that the animations move; null when no channel moves them).
    std::vector<ref_ptr<Animation>> animations;
    // The node built for each glTF node of the default scene, by glTF node index (a Transform, or the Transform
    // around one of sgkit's own kinds); null where none was built. A program finds a file's nodes here by index.
    std::vector<ref_ptr<Node>> nodes;
    std::shared_ptr<std::vector<PunctualLight>> animatedLights;
    std::shared_ptr<std::vector<GltfCamera>> animatedCameras;
};

// Throws LoadError; never crashes, hangs or leaks on any input. Points and lines are read as Meshes of those
// primitives; the _INTENSITY attribute (a SCALAR, any component type: integers and floats as the value, normalized
// integers as a fraction of 65535) becomes Mesh::intensities(), CESIUM_primitive_outline Mesh::outline().
GltfScene loadGltf(const std::string& path, const GltfLoadOptions& options = {});
// The same from memory (`name` is used in messages; binary when the data starts with "glTF").
GltfScene loadGltfFromMemory(const std::string& name, const void* data, size_t size,
                             const GltfLoadOptions& options = {});

// A pager's load function (sg::Pager): the root of a glTF file's default scene; throws LoadError.
ref_ptr<Node> loadGltfPage(const std::string& file);

// Writes the graph below `root` as .glb or .gltf (embedded buffers), chosen by the extension.
// Throws std::runtime_error naming the file when it cannot be written.
void saveGltf(const Node& root, const std::string& path, const GltfSaveOptions& options = {});

}  // namespace sg
