// saveGltf's part for motion: skins (JOINTS_n/WEIGHTS_n and the skin's joints and inverse bind matrices), morph
// targets and their weights, and animations with their samplers and channels, KHR_animation_pointer included
// (GltfWriteMotion.cpp, GltfWriteAnimations.cpp). Internal.
#pragma once
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/core/Animation.h"

#include <tiny_gltf.h>

#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace sg::gltf {

class MotionWriter {
public:
    // `view` appends bytes to the buffer as a new buffer view (with a target, 0 for none) and gives its index;
    // `warnings` (may be null) hears what is left out.
    MotionWriter(tinygltf::Model& m, std::function<int(const void*, size_t, int)> view,
                 std::vector<std::string>* warnings, const std::vector<ref_ptr<Animation>>& animations);

    // Whether the node must stay a glTF node of its own (a channel drives it, or a posed Geometry): not folded
    // into an instanced batch.
    bool pinned(const Node& n) const;
    // An animated Transform as translation, rotation and scale (glTF forbids a matrix on a node whose TRS a channel
    // drives); false when no channel drives it, or its matrix has a shear (then written as a matrix, its channels
    // left out).
    bool trs(const Transform& t, tinygltf::Node& gn);
    // Node n was written as glTF node `index` (the first index counts for a node written along several paths).
    void written(const Node& n, int index);
    // Primitive p's JOINTS_n and WEIGHTS_n from its mesh's skin weights.
    void skinAttributes(const Mesh& mesh, tinygltf::Primitive& p);
    // Primitive p's morph targets and the mesh's weights (Mesh::defaultWeights) in gm.
    void morphTargets(const Mesh& mesh, tinygltf::Primitive& p, tinygltf::Mesh& gm);
    // A Geometry's morph weights as the node's weights (one per target) when it has some.
    static void nodeWeights(const Geometry& g, tinygltf::Node& gn);
    // Skins, then animations, once every node is written. `mesh` writes a Geometry's mesh with or without its skin
    // attributes (a skin left out leaves a mesh without them: glTF pairs the two) and gives its index.
    void finish(const std::function<int(const Geometry&, bool skinned)>& mesh);
    // Whether a channel went out as KHR_animation_pointer (see withoutPointerNodes).
    bool pointers() const { return pointers_; }

private:
    template <class T>
    int accessor(const std::vector<T>& v, int comp, int type, size_t count, int target);
    int floats(const std::vector<float>& v, int type, size_t count) {
        return accessor(v, TINYGLTF_COMPONENT_TYPE_FLOAT, type, count, 0);
    }
    void warn(const std::string& what);
    // The glTF skin for `skin` (written once); -1, with a warning, when a joint is not written or the joints have no
    // common root.
    int skin(const Skin& skin);
    bool commonRoot(const std::vector<int>& joints) const;
    // Animation a, its channels that can be written; left out whole when none can.
    void animation(const Animation& a, size_t index);
    // The glTF nodes a channel drives: its node's, or for weights the Geometries' below it.
    std::vector<int> channelTargets(const AnimationChannel& c, uint32_t width, const std::string& path);
    // The glTF samplers written for an animation, by sampler, rotation (normalised) and output width.
    using SamplerKeys = std::map<std::tuple<const AnimationSampler*, bool, uint32_t>, int>;
    // Sampler s of a channel into ga (once per key): its times, and its values `outWidth` to an element.
    int sampler(const AnimationSampler& s, bool rotation, uint32_t outWidth, tinygltf::Animation& ga,
                SamplerKeys& done);

    tinygltf::Model& m_;
    std::function<int(const void*, size_t, int)> view_;
    std::vector<std::string>* warnings_;
    const std::vector<ref_ptr<Animation>>& animations_;
    std::set<const Node*> driven_;     // nodes some channel names
    std::set<const Node*> trsDriven_;  // Transforms whose translation, rotation or scale a channel drives
    std::set<const Node*> sheared_;    // of those, the ones written as a matrix
    std::map<const Node*, int> index_;
    std::vector<std::pair<int, const Geometry*>> skinned_;
    std::map<const Mesh*, std::map<std::string, int>> skinAttributes_;
    std::map<const Mesh*, std::vector<std::map<std::string, int>>> targets_;
    std::map<const Skin*, int> skins_;
    bool pointers_ = false;
};

// The written file with the node of each KHR_animation_pointer channel's target removed: tinygltf writes a node
// index (-1) on every channel, and the extension wants none. `bytes` is the .gltf's JSON or the .glb.
std::string withoutPointerNodes(const std::string& bytes, bool glb);

}  // namespace sg::gltf
