// glTF morph targets: a primitive's POSITION, NORMAL and TANGENT displacements read into its Mesh, the target counts
// of a mesh's primitives checked against each other and against the mesh's and its nodes' weights.
#include "loaders/gltf/internal/GltfConverter.h"

#include <cmath>

namespace sg::gltf {

std::string Converter::motionKey(const tinygltf::Primitive& p, int gm) {
    std::string key;
    for (const char* name : {"JOINTS_0", "WEIGHTS_0", "JOINTS_1", "WEIGHTS_1"}) {
        auto it = p.attributes.find(name);
        key += ',' + std::to_string(it == p.attributes.end() ? -1 : it->second);
    }
    if (p.targets.empty()) return key;
    key += ";m" + std::to_string(gm);  // the Mesh holds its glTF mesh's default weights
    for (const auto& t : p.targets) {
        key += ';';
        for (const auto& [name, acc] : t) key += name + '=' + std::to_string(acc) + ',';
    }
    return key;
}

void Converter::morphTargets(const tinygltf::Primitive& p, Mesh& mesh, const std::string& path, int gm,
                             const std::vector<uint32_t>* order) {
    if (p.targets.empty()) return;
    const size_t n = m.accessors[size_t(p.attributes.at("POSITION"))].count;
    // KHR_mesh_quantization: positions of signed bytes or shorts (normalized or not), normals and tangents of
    // normalized ones.
    auto used = [&](const std::vector<std::string>& v) {
        return std::find(v.begin(), v.end(), kQuantization) != v.end();
    };
    const bool quantized = used(m.extensionsUsed) || used(m.extensionsRequired);
    targetBytes += p.targets.size() * sizeof(MorphTarget);  // empty targets cost their vectors
    if (targetBytes > kMaxExpandedBytes)
        bad(path + ".targets",
            "the file's morph targets come to more than " + std::to_string(kMaxExpandedBytes >> 20) + " MiB");
    std::vector<MorphTarget> targets(p.targets.size());
    for (size_t t = 0; t < p.targets.size(); ++t) {
        for (const auto& [name, acc] : p.targets[t]) {
            const std::string tp = at(path + ".targets", t) + "." + name;
            const bool position = name == "POSITION";
            if (!position && name != "NORMAL" && name != "TANGENT") {
                warn(tp, "not read: only POSITION, NORMAL and TANGENT targets are");
                continue;
            }
            if (acc < 0 || size_t(acc) >= m.accessors.size())
                bad(tp, "accessor " + std::to_string(acc) + " does not exist (" + std::to_string(m.accessors.size()) +
                            " accessors)");
            const tinygltf::Accessor& a = m.accessors[size_t(acc)];
            const bool small =
                a.componentType == TINYGLTF_COMPONENT_TYPE_BYTE || a.componentType == TINYGLTF_COMPONENT_TYPE_SHORT;
            if (a.type != TINYGLTF_TYPE_VEC3 || !(a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                                                  (quantized && small && (position || a.normalized))))
                bad(tp, "accessor " + std::to_string(acc) + " is not VEC3 of floats" +
                            (quantized ? position ? " or of signed bytes or shorts"
                                                  : " or of normalized signed bytes or shorts"
                                       : ""));
            if (a.count != n)
                bad(tp, "count " + std::to_string(a.count) + " differs from the primitive's " + std::to_string(n) +
                            " vertices");
            targetBytes += a.count * sizeof(vec3);
            if (targetBytes > kMaxExpandedBytes)
                bad(tp,
                    "the file's morph targets come to more than " + std::to_string(kMaxExpandedBytes >> 20) + " MiB");
            std::vector<vec3> d = readVectors<vec3, 3>(m, acc);
            for (size_t i = 0; i < d.size(); ++i)
                if (!std::isfinite(d[i].x) || !std::isfinite(d[i].y) || !std::isfinite(d[i].z))
                    bad(tp, "element " + std::to_string(i) + " is not finite");
            if (order) {  // indexed points: each point's displacement at its index
                std::vector<vec3> g;
                g.reserve(order->size());
                for (uint32_t i : *order) g.push_back(d[i]);
                d = std::move(g);
            }
            (position           ? targets[t].positions
             : name == "NORMAL" ? targets[t].normals
                                : targets[t].tangents) = std::move(d);
        }
    }
    try {
        mesh.setMorphTargets(std::move(targets));
    } catch (const std::invalid_argument& e) {  // counts checked above: not expected
        bad(path + ".targets", e.what());
    }
    const std::vector<double>& w = m.meshes[size_t(gm)].weights;  // targetCount() has checked the length
    mesh.defaultWeights.clear();
    for (size_t k = 0; k < w.size(); ++k)
        mesh.defaultWeights.push_back(toFloat(w[k], at(at("meshes", size_t(gm)) + ".weights", k)));
}

size_t Converter::targetCount(int i) {
    if (auto it = targetCounts.find(i); it != targetCounts.end()) return it->second;
    const tinygltf::Mesh& gm = m.meshes[size_t(i)];
    const std::string path = at("meshes", size_t(i));
    const size_t count = gm.primitives.empty() ? 0 : gm.primitives[0].targets.size();
    for (size_t k = 1; k < gm.primitives.size(); ++k)
        if (gm.primitives[k].targets.size() != count)
            bad(at(path + ".primitives", k) + ".targets",
                std::to_string(gm.primitives[k].targets.size()) + " morph targets, primitives[0] has " +
                    std::to_string(count) + " (every primitive of a mesh has the same targets)");
    if (!gm.weights.empty() && gm.weights.size() != count)
        bad(path + ".weights",
            std::to_string(gm.weights.size()) + " weights for " + std::to_string(count) + " morph targets");
    return targetCounts[i] = count;
}

std::vector<float> Converter::startWeights(int i) {
    const tinygltf::Node& gn = m.nodes[size_t(i)];
    const size_t count = targetCount(gn.mesh);
    const bool own = !gn.weights.empty();
    const std::string path = own ? at("nodes", size_t(i)) + ".weights" : at("meshes", size_t(gn.mesh)) + ".weights";
    if (own && gn.weights.size() != count)
        bad(path, std::to_string(gn.weights.size()) + " weights for the " + std::to_string(count) +
                      " morph targets of meshes[" + std::to_string(gn.mesh) + "]");
    std::vector<float> out;
    for (double v : own ? gn.weights : m.meshes[size_t(gn.mesh)].weights) {
        out.push_back(toFloat(v, at(path, out.size())));  // refuses what is not finite too
    }
    return out;
}

}  // namespace sg::gltf
