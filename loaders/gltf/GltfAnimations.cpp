// glTF animations as sg::Animations bound to the nodes built from the file: samplers checked and read as floats
// (normalized integers by the spec's formulas), channels bound to the Transforms and Geometries of their nodes.
// KHR_animation_pointer's channels are bound in GltfAnimationPointer.cpp.
#include "loaders/gltf/internal/GltfConverter.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string_view>

namespace sg::gltf {

namespace {

// Floats all the samplers of a file may hold: one accessor read by many samplers must not stand for gigabytes.
constexpr size_t kMaxAnimationValues = size_t(1) << 27;

bool isInteger(int comp) {
    return comp == TINYGLTF_COMPONENT_TYPE_BYTE || comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           comp == TINYGLTF_COMPONENT_TYPE_SHORT || comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
}

Interpolation interpolation(const std::string& s) {
    return s == "STEP" ? Interpolation::Step : s == "CUBICSPLINE" ? Interpolation::CubicSpline : Interpolation::Linear;
}

// The Geometries of a glTF node's mesh: the node itself for sgkit's Geometry kind, else the Geometry children of the
// node nodeOf holds (a Transform), less those that are glTF nodes of their own (sgkit Geometries without a matrix).
std::vector<ref_ptr<Node>> meshGeometries(Node* node, const std::unordered_set<const Node*>& built) {
    if (node->kind() == NodeKind::Geometry) return {ref_ptr<Node>(node)};
    std::vector<ref_ptr<Node>> out;
    for (size_t k = 0; k < node->numChildren(); ++k) {
        Node* g = node->child(k);
        if (g->kind() == NodeKind::Geometry && !built.count(g)) out.push_back(ref_ptr<Node>(g));
    }
    return out;
}

}  // namespace

void restorePointerChannels(const unsigned char* data, size_t size, bool binary, tinygltf::Model& model) {
    if (model.animations.empty()) return;
    size_t jsonAt = 0, jsonLen = size;
    if (binary) {  // prevalidate() has checked the header and the chunk lengths
        jsonAt = 20;
        jsonLen = size_t(data[12]) | size_t(data[13]) << 8 | size_t(data[14]) << 16 | size_t(data[15]) << 24;
    }
    const std::string_view text(reinterpret_cast<const char*>(data) + jsonAt, jsonLen);
    if (text.find(kAnimationPointer) == std::string_view::npos) return;  // most files: nothing parsed twice
    const nlohmann::json j = nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("animations") || !j["animations"].is_array() ||
        j["animations"].size() != model.animations.size())
        return;
    // An index as tinygltf reads one: -1 when absent, -2 (no such element) when it is not an int.
    auto index = [](const nlohmann::json& o, const char* key) {
        if (!o.is_object() || !o.contains(key)) return -1;
        const nlohmann::json& v = o[key];
        return v.is_number_integer() && v.get<long long>() >= 0 && v.get<long long>() <= 0x7fffffff
                   ? int(v.get<long long>())
                   : -2;
    };
    for (size_t a = 0; a < model.animations.size(); ++a) {
        const nlohmann::json& ja = j["animations"][a];
        if (!ja.is_object() || !ja.contains("channels") || !ja["channels"].is_array()) continue;
        std::vector<tinygltf::AnimationChannel> channels;
        for (const nlohmann::json& jc : ja["channels"]) {
            tinygltf::AnimationChannel c;
            c.sampler = index(jc, "sampler");
            const nlohmann::json target = jc.is_object() && jc.contains("target") ? jc["target"] : nlohmann::json();
            c.target_node = index(target, "node");
            if (target.is_object() && target.contains("path") && target["path"].is_string())
                c.target_path = target["path"].get<std::string>();
            const nlohmann::json* x = target.is_object() && target.contains("extensions") &&
                                              target["extensions"].is_object() &&
                                              target["extensions"].contains(kAnimationPointer)
                                          ? &target["extensions"][kAnimationPointer]
                                          : nullptr;
            if (x) {
                tinygltf::Value::Object o;
                if (x->is_object() && x->contains("pointer") && (*x)["pointer"].is_string())
                    o["pointer"] = tinygltf::Value((*x)["pointer"].get<std::string>());
                c.target_extensions[kAnimationPointer] = tinygltf::Value(std::move(o));
            }
            channels.push_back(std::move(c));
        }
        model.animations[a].channels = std::move(channels);
    }
}

void Converter::samplerTimes(AnimationRead& r, size_t s) {
    const tinygltf::AnimationSampler& gs = r.ga.samplers[s];
    const std::string sp = r.path("samplers", s);
    const size_t na = m.accessors.size();
    if (gs.input < 0 || size_t(gs.input) >= na)
        bad(sp + ".input",
            "accessor " + std::to_string(gs.input) + " does not exist (" + std::to_string(na) + " accessors)");
    if (gs.output < 0 || size_t(gs.output) >= na)
        bad(sp + ".output",
            "accessor " + std::to_string(gs.output) + " does not exist (" + std::to_string(na) + " accessors)");
    if (gs.interpolation != "LINEAR" && gs.interpolation != "STEP" && gs.interpolation != "CUBICSPLINE")
        bad(sp + ".interpolation", "unknown interpolation '" + gs.interpolation + "'");
    const tinygltf::Accessor& in = m.accessors[size_t(gs.input)];
    if (in.type != TINYGLTF_TYPE_SCALAR || in.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        bad(sp + ".input", "accessor " + std::to_string(gs.input) + " is " + typeName(in.type) + " of componentType " +
                               std::to_string(in.componentType) + ", needs SCALAR of componentType 5126 (float times)");
    const AccessorReader reader(m, in);
    std::vector<float>& t = r.times[s];
    for (size_t k = 0; k < in.count; ++k) {  // checked as read: a bad file fails before its whole accessor is copied
        const float v = reader.component(k, 0);
        if (!std::isfinite(v)) bad(sp + ".input", "time " + std::to_string(k) + " is not finite");
        if (k > 0 && !(v > t.back()))
            bad(sp + ".input", "times are not strictly increasing: time " + std::to_string(k) + " (" +
                                   std::to_string(v) + ") is not after time " + std::to_string(k - 1) + " (" +
                                   std::to_string(t.back()) + ")");
        t.push_back(v);
    }
}

uint32_t Converter::channelSampler(AnimationRead& r, size_t c, int type, uint32_t width, Outputs outputs,
                                   const std::string& what) {
    const int s = r.ga.channels[c].sampler;
    if (s < 0 || size_t(s) >= r.ga.samplers.size())
        bad(r.path("channels", c) + ".sampler",
            "sampler " + std::to_string(s) + " does not exist (" + std::to_string(r.ga.samplers.size()) + " samplers)");
    const tinygltf::AnimationSampler& gs = r.ga.samplers[size_t(s)];
    const std::string op = r.path("samplers", size_t(s)) + ".output";
    const tinygltf::Accessor& out = m.accessors[size_t(gs.output)];
    const int comp = out.componentType;
    const bool compOk =
        comp == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        (isInteger(comp) && (outputs == Outputs::Integers || out.normalized) && outputs != Outputs::Float);
    const char* allowed = outputs == Outputs::Float        ? "floats"
                          : outputs == Outputs::Normalized ? "floats or normalized integers"
                                                           : "floats or byte or short integers";
    if (out.type != type || !compOk)
        bad(op, "accessor " + std::to_string(gs.output) + " is " + typeName(out.type) + " of componentType " +
                    std::to_string(comp) + (out.normalized ? " (normalized)" : "") + ", " + what + " needs " +
                    typeName(type) + " of " + allowed);
    const bool cubic = gs.interpolation == "CUBICSPLINE";
    const int components = tinygltf::GetNumComponentsInType(uint32_t(type));
    const size_t keys = m.accessors[size_t(gs.input)].count, perKey = width / uint32_t(components);
    const size_t want = keys * perKey * (cubic ? 3 : 1);
    if (out.count != want)
        bad(op, "count " + std::to_string(out.count) + " does not match the input's " + std::to_string(keys) +
                    " keys: " + what + " needs " + std::to_string(want) + " (" +
                    (perKey > 1 ? std::to_string(perKey) + " a key" : std::string("one a key")) +
                    (cubic ? ", each an in-tangent, a value and an out-tangent)" : ")"));
    int& made = r.samplerOf[size_t(s)];
    if (made >= 0) {  // read for an earlier channel: the same width, else the two cannot share it
        if (r.anim.samplers[size_t(made)].width != width)
            bad(r.path("channels", c) + ".sampler",
                "sampler " + std::to_string(s) + " has " + std::to_string(r.anim.samplers[size_t(made)].width) +
                    " values a key for another channel, " + what + " needs " + std::to_string(width));
        return uint32_t(made);
    }
    const size_t n = out.count * size_t(components);
    if (n > kMaxAnimationValues - std::min(kMaxAnimationValues, animationValues))
        bad(op, "the file's animations hold more than " + std::to_string(kMaxAnimationValues) + " values");
    animationValues += n;
    AnimationSampler as;
    as.width = width;
    as.interpolation = interpolation(gs.interpolation);
    as.values.reserve(n);
    const AccessorReader reader(m, out);
    for (size_t k = 0; k < out.count; ++k)
        for (int i = 0; i < components; ++i) {
            const float v = reader.component(k, i);
            if (!std::isfinite(v)) bad(op, "element " + std::to_string(k) + " is not finite");
            as.values.push_back(v);
        }
    as.times = std::move(r.times[size_t(s)]);
    made = int(r.anim.samplers.size());
    r.anim.samplers.push_back(std::move(as));
    return uint32_t(made);
}

void Converter::nodeChannel(AnimationRead& r, size_t c, int node, const std::string& path, const std::string& where) {
    const size_t nn = m.nodes.size();
    if (node < 0 || size_t(node) >= nn)
        bad(where, "node " + std::to_string(node) + " does not exist (" + std::to_string(nn) + " nodes)");
    const tinygltf::Node& gn = m.nodes[size_t(node)];
    Node* built = nodeOf[size_t(node)].get();
    if (!built) {
        warn(r.path("channels", c),
             "node " + std::to_string(node) + " was not built (not in the scene, or skipped)" + ": channel skipped");
        return;
    }
    AnimationChannel ch;
    ch.target = gn.name.empty() ? at("nodes", size_t(node)) : gn.name;
    if (path == "weights") {
        const auto* mesh = gn.mesh >= 0 ? &m.meshes[size_t(gn.mesh)] : nullptr;
        const size_t targets = mesh && !mesh->primitives.empty() ? mesh->primitives[0].targets.size() : 0;
        if (targets == 0)
            bad(where, "node " + std::to_string(node) + " has no mesh with morph targets for its weights");
        // A node with a skin or morph targets has Geometries of its own (a skinned one's sit under the root, not
        // below its Transform); others share their mesh's, found below the node.
        std::vector<ref_ptr<Node>> geometries;
        if (auto own = nodeGeometries.find(node); own != nodeGeometries.end())
            geometries.assign(own->second.begin(), own->second.end());
        else
            geometries = meshGeometries(built, r.built);
        if (geometries.empty()) {
            warn(r.path("channels", c), "node " + std::to_string(node) + "'s mesh was not built as Geometries" +
                                            " (instanced, or its kind ignores it): channel skipped");
            return;
        }
        ch.path = AnimationPath::Weights;
        ch.sampler = channelSampler(r, c, TINYGLTF_TYPE_SCALAR, uint32_t(targets), Outputs::Normalized, "weights");
        for (const ref_ptr<Node>& g : geometries) {  // one channel a primitive, on one sampler
            ch.node = g;
            r.anim.channels.push_back(ch);
        }
        return;
    }
    if (built->kind() != NodeKind::Transform) {
        warn(r.path("channels", c), "node " + std::to_string(node) + " is built as an sgkit " + built->kindName() +
                                        ", not a Transform (it has no matrix): channel skipped");
        return;
    }
    const bool rotation = path == "rotation";
    const bool quantized =
        std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), kQuantization) != m.extensionsUsed.end();
    ch.path = rotation ? AnimationPath::Rotation : path == "scale" ? AnimationPath::Scale : AnimationPath::Translation;
    ch.node = built;
    ch.sampler = channelSampler(r, c, rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, rotation ? 4 : 3,
                                rotation    ? Outputs::Normalized
                                : quantized ? Outputs::Integers
                                            : Outputs::Float,
                                path);
    r.anim.channels.push_back(std::move(ch));
}

void Converter::animations() {
    std::unordered_set<const Node*> built;
    for (const auto& n : nodeOf) built.insert(n.get());
    for (size_t a = 0; a < m.animations.size(); ++a) {
        const tinygltf::Animation& ga = m.animations[a];
        auto anim = make<Animation>();
        anim->name = ga.name;
        AnimationRead r{a,
                        ga,
                        *anim,
                        built,
                        std::vector<int>(ga.samplers.size(), -1),
                        std::vector<std::vector<float>>(ga.samplers.size())};
        for (size_t s = 0; s < ga.samplers.size(); ++s) samplerTimes(r, s);
        for (size_t c = 0; c < ga.channels.size(); ++c) {
            const tinygltf::AnimationChannel& gc = ga.channels[c];
            const std::string cp = r.path("channels", c);
            const std::string& path = gc.target_path;
            if (path == "pointer") {
                pointerChannel(r, c);
            } else if (path != "translation" && path != "rotation" && path != "scale" && path != "weights") {
                warn(cp + ".target.path", "unknown path '" + path + "': channel skipped");
            } else if (gc.target_node == -1) {  // glTF: a channel without a node is ignored
                warn(cp + ".target", "no node: channel skipped");
            } else {
                nodeChannel(r, c, gc.target_node, path, cp + ".target.node");
            }
        }
        try {
            anim->validate();
        } catch (const std::invalid_argument& e) {
            bad(at("animations", a), e.what());
        }
        out.animations.push_back(anim);
    }
}

}  // namespace sg::gltf
