// KHR_lights_punctual: a node's light into the scene's list, in world axes, checked against the extension's ranges.
#include "loaders/gltf/internal/GltfDetail.h"

#include <cmath>

namespace sg::gltf {

namespace {

bool finite(double v) { return std::isfinite(v); }

// Why the light cannot be used, or empty.
std::string problem(const tinygltf::Light& l) {
    if (l.type != "directional" && l.type != "point" && l.type != "spot") return "unknown type '" + l.type + "'";
    if (!l.color.empty()) {
        if (l.color.size() != 3) return "color must have 3 components";
        for (double c : l.color)
            if (!finite(c) || c < 0.0 || c > 1.0) return "color components must be in [0, 1]";
    }
    if (!finite(l.intensity) || l.intensity < 0.0 || l.intensity > 1e30) return "intensity must be finite and >= 0";
    if (!finite(l.range) || l.range < 0.0 || l.range > 1e30) return "range must be finite and > 0 where given";
    if (l.type == "spot") {
        const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
        if (!finite(inner) || !finite(outer) || inner < 0.0 || outer <= inner || outer > glm::half_pi<double>())
            return "spot cone must have 0 <= innerConeAngle < outerConeAngle <= pi/2";
    }
    return {};
}

}  // namespace

int nodeLight(const tinygltf::Model& model, const tinygltf::Node& node, const std::string& nodePath, const dmat4& world,
              std::vector<PunctualLight>& lights, std::vector<std::string>& warnings) {
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end()) return -1;
    const std::string path = nodePath + ".extensions.KHR_lights_punctual.light";
    const tinygltf::Value& index = ext->second.Get("light");
    if (!index.IsNumber() || index.GetNumberAsDouble() != std::floor(index.GetNumberAsDouble()) ||
        index.GetNumberAsDouble() < 0 || index.GetNumberAsDouble() >= double(model.lights.size())) {
        warnings.push_back(path + ": not the index of a light; the light is skipped");
        return -1;
    }
    const size_t i = size_t(index.GetNumberAsDouble());
    const tinygltf::Light& l = model.lights[i];
    const std::string why = problem(l);
    if (!why.empty()) {
        warnings.push_back("extensions.KHR_lights_punctual.lights[" + std::to_string(i) + "]: " + why +
                           "; the light is skipped");
        return -1;
    }
    PunctualLight p;
    p.type = l.type == "directional" ? PunctualLight::Type::Directional
             : l.type == "point"     ? PunctualLight::Type::Point
                                     : PunctualLight::Type::Spot;
    p.position = dvec3(world[3]);
    const dvec3 down = glm::dmat3(world) * dvec3(0.0, 0.0, -1.0);
    const double len = glm::length(down);
    if (p.type != PunctualLight::Type::Point && !(len > 0.0 && finite(len))) {
        warnings.push_back(path + ": the node's matrix gives the light no direction; the light is skipped");
        return -1;
    }
    if (p.type != PunctualLight::Type::Point) p.direction = vec3(down / len);
    if (!l.color.empty()) p.color = vec3(float(l.color[0]), float(l.color[1]), float(l.color[2]));
    p.intensity = float(l.intensity);
    p.range = float(l.range);
    if (p.type == PunctualLight::Type::Spot) {
        p.innerConeAngle = float(l.spot.innerConeAngle);
        p.outerConeAngle = float(l.spot.outerConeAngle);
    }
    lights.push_back(p);
    return int(i);
}

}  // namespace sg::gltf
