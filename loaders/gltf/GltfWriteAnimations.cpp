// Animations as glTF writes them: each sampler a channel uses as a float input (with the bounds glTF asks) and a
// float output, each channel on the written node it drives, property channels as KHR_animation_pointer. What
// glTF cannot hold (negative times, a node not written, the same target twice) is left out with a warning.
#include "loaders/gltf/internal/GltfWriteMotion.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

namespace sg::gltf {
namespace {

constexpr const char* kPointer = "KHR_animation_pointer";

const char* interpolationName(Interpolation i) {
    switch (i) {
        case Interpolation::Step: return "STEP";
        case Interpolation::CubicSpline: return "CUBICSPLINE";
        case Interpolation::Linear: break;
    }
    return "LINEAR";
}

// The output accessor's type for `width` floats a key (weights and wide properties: scalars, as glTF lays them out).
int outputType(uint32_t width) {
    return width == 2   ? TINYGLTF_TYPE_VEC2
           : width == 3 ? TINYGLTF_TYPE_VEC3
           : width == 4 ? TINYGLTF_TYPE_VEC4
                        : TINYGLTF_TYPE_SCALAR;
}

// The Geometries below n that a weights channel on n drives: those up to the next Transform (a glTF node's
// primitives), not inside Instances (whose prototypes are shared).
void geometriesBelow(const Node& n, std::vector<const Geometry*>& out) {
    for (size_t i = 0; i < n.numChildren(); ++i) {
        const Node* c = n.child(i);
        if (!c || c->kind() == NodeKind::Transform || c->kind() == NodeKind::Instance) continue;
        if (c->kind() == NodeKind::Geometry)
            out.push_back(static_cast<const Geometry*>(c));
        else
            geometriesBelow(*c, out);
    }
}

}  // namespace

std::vector<int> MotionWriter::channelTargets(const AnimationChannel& c, uint32_t width, const std::string& where) {
    if (!c.node) {
        warn(where + ": no node; left out");
        return {};
    }
    const auto found = index_.find(c.node.get());
    if (c.path != AnimationPath::Weights) {
        if (found == index_.end()) {
            warn(where + ": its node '" + c.node->name() + "' is not below the root written; left out");
            return {};
        }
        if (sheared_.count(c.node.get())) {
            warn(where + ": its Transform '" + c.node->name() + "' has a shear, written as a matrix; left out");
            return {};
        }
        return {found->second};
    }
    std::vector<const Geometry*> geometries;
    if (c.node->kind() == NodeKind::Geometry)
        geometries.push_back(static_cast<const Geometry*>(c.node.get()));
    else
        geometriesBelow(*c.node, geometries);
    std::vector<int> out;
    for (const Geometry* g : geometries) {
        const auto at = index_.find(g);
        const Mesh* mesh = g->mesh();
        // glTF's weights channel needs a node with a mesh of as many morph targets.
        if (at != index_.end() && mesh && mesh->primitiveCount() > 0 && mesh->morphTargets().size() == width)
            out.push_back(at->second);
    }
    if (out.empty())
        warn(where + ": no written Geometry with " + std::to_string(width) + " morph targets at or below its node '" +
             c.node->name() + "'; left out");
    return out;
}

int MotionWriter::sampler(const AnimationSampler& s, bool rotation, uint32_t outWidth, tinygltf::Animation& ga,
                          SamplerKeys& done) {
    const auto key = std::make_tuple(&s, rotation, outWidth);
    if (auto it = done.find(key); it != done.end()) return it->second;
    tinygltf::AnimationSampler gs;
    gs.interpolation = interpolationName(s.interpolation);
    gs.input = floats(s.times, TINYGLTF_TYPE_SCALAR, s.times.size());
    m_.accessors.back().minValues = {s.times.front()};
    m_.accessors.back().maxValues = {s.times.back()};
    std::vector<float> values = s.values;
    if (rotation) {
        // glTF asks unit quaternions of a rotation's keys (a spline's tangents are free): a value off unit length
        // by more than float's rounding is normalised.
        const size_t group = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
        for (size_t k = 0; k + 4 * group <= values.size(); k += 4 * group) {
            float* q = values.data() + k + (group == 3 ? 4 : 0);
            const double len =
                std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
            if (len > 0.0 && std::abs(len - 1.0) > 1e-5)
                for (int c = 0; c < 4; ++c) q[c] = float(q[c] / len);
        }
    }
    gs.output = floats(values, outputType(outWidth), values.size() / outWidth);
    ga.samplers.push_back(std::move(gs));
    return done[key] = int(ga.samplers.size() - 1);
}

void MotionWriter::animation(const Animation& a, size_t index) {
    const std::string where =
        "saveGltf(): animations[" + std::to_string(index) + "]" + (a.name.empty() ? "" : " '" + a.name + "'");
    try {
        a.validate();
    } catch (const std::invalid_argument& e) {
        warn(where + ": " + e.what() + "; left out");
        return;
    }
    tinygltf::Animation ga;
    ga.name = a.name;
    SamplerKeys done;
    std::set<std::pair<int, AnimationPath>> nodeTargets;  // glTF: a target once an animation
    std::set<std::string> pointerTargets;
    for (size_t k = 0; k < a.channels.size(); ++k) {
        const AnimationChannel& c = a.channels[k];
        const std::string cw = where + ".channels[" + std::to_string(k) + "]";
        const AnimationSampler& s = a.samplers[c.sampler];  // validate() checked the index
        if (s.times.front() < 0.0f) {
            warn(cw + ": its keys start before time 0 (glTF's times are not negative); left out");
            continue;
        }
        if (s.interpolation == Interpolation::CubicSpline && s.times.size() < 2) {
            warn(cw + ": a cubic spline of one key (glTF asks two); left out");
            continue;
        }
        const bool rotation = c.path == AnimationPath::Rotation;
        // The output's width as glTF's accessor type counts it (weights: scalars).
        const uint32_t outWidth = c.path == AnimationPath::Translation || c.path == AnimationPath::Scale ? 3
                                  : rotation                                                             ? 4
                                  : c.path == AnimationPath::Property && s.width <= 4                    ? s.width
                                                                                                         : 1;
        if (c.path == AnimationPath::Property) {
            if (c.target.empty() || c.target[0] != '/') {
                warn(cw + ": a property channel without a KHR_animation_pointer ('" + c.target + "'); left out");
                continue;
            }
            if (!pointerTargets.insert(c.target).second) {
                warn(cw + ": drives '" + c.target + "' again in this animation; left out");
                continue;
            }
            tinygltf::AnimationChannel gc;
            gc.sampler = sampler(s, false, outWidth, ga, done);
            gc.target_path = "pointer";
            gc.target_extensions[kPointer] =
                tinygltf::Value(tinygltf::Value::Object{{"pointer", tinygltf::Value(c.target)}});
            ga.channels.push_back(std::move(gc));
            pointers_ = true;
            continue;
        }
        for (int node : channelTargets(c, s.width, cw)) {
            if (!nodeTargets.emplace(node, c.path).second) {
                warn(cw + ": drives the " + pathName(c.path) + " of glTF node " + std::to_string(node) +
                     " again in this animation; left out");
                continue;
            }
            tinygltf::AnimationChannel gc;
            gc.sampler = sampler(s, rotation, outWidth, ga, done);
            gc.target_node = node;
            gc.target_path = pathName(c.path);
            ga.channels.push_back(std::move(gc));
        }
    }
    if (ga.channels.empty()) {
        warn(where + ": no channel can be written; left out");
        return;
    }
    m_.animations.push_back(std::move(ga));
    if (pointers_ && std::find(m_.extensionsUsed.begin(), m_.extensionsUsed.end(), kPointer) == m_.extensionsUsed.end())
        m_.extensionsUsed.push_back(kPointer);
}

std::string withoutPointerNodes(const std::string& bytes, bool glb) {
    using json = nlohmann::ordered_json;
    const auto fix = [](json& j) {
        const auto animations = j.find("animations");
        if (animations == j.end()) return;
        for (json& a : *animations)
            for (json& c : a["channels"])
                if (json& t = c["target"]; t.value("path", "") == "pointer") t.erase("node");
    };
    if (!glb) {
        json j = json::parse(bytes);
        fix(j);
        return j.dump(2);
    }
    // A GLB: a 12-byte header (magic, version, length), the JSON chunk (length, type, text padded with spaces to
    // four bytes), then the binary chunk, all little-endian; only the JSON chunk changes.
    uint32_t jsonLength = 0;
    if (bytes.size() < 20) return bytes;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    if (jsonLength > bytes.size() - 20) return bytes;
    json j = json::parse(bytes.substr(20, jsonLength));
    fix(j);
    std::string text = j.dump();
    text.resize((text.size() + 3) & ~size_t(3), ' ');
    const std::string rest = bytes.substr(20 + size_t(jsonLength));
    std::string out = bytes.substr(0, 20);
    const uint32_t total = uint32_t(20 + text.size() + rest.size()), length = uint32_t(text.size());
    std::memcpy(&out[8], &total, 4);
    std::memcpy(&out[12], &length, 4);
    return out + text + rest;
}

}  // namespace sg::gltf
