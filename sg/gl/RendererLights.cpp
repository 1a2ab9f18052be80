// Renderer: the lights of the next draws, checked when set, and what a frame's programs get of them.
#include "sg/gl/Renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace sg {

void Renderer::setLight(const DirectionalLight& light) {
    const float len = glm::length(light.direction);
    if (!light.headlight && !(len > 0.0f && std::isfinite(len)))
        throw std::invalid_argument(
            "Renderer::setLight(): the direction of a light that is not the headlight must be "
            "finite and non-zero");
    light_ = light;
}

void Renderer::setPunctualLights(std::vector<PunctualLight> lights) {
    if (lights.size() > kMaxLights)
        throw std::invalid_argument("Renderer::setPunctualLights(): " + std::to_string(lights.size()) +
                                    " lights, at most " + std::to_string(kMaxLights));
    for (size_t k = 0; k < lights.size(); ++k) {
        const PunctualLight& l = lights[k];
        const auto bad = [&](const char* field, const char* why) {
            throw std::invalid_argument("Renderer::setPunctualLights(): lights[" + std::to_string(k) + "]." + field +
                                        " " + why);
        };
        const auto finite3 = [](const auto& v) {
            return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
        };
        if (!finite3(l.position)) bad("position", "is not finite");
        if (!finite3(l.direction) || !(glm::length(l.direction) > 0.0f)) bad("direction", "is zero or not finite");
        if (!finite3(l.color) || l.color.r < 0.0f || l.color.g < 0.0f || l.color.b < 0.0f)
            bad("color", "is negative or not finite");
        if (!(l.intensity >= 0.0f) || !std::isfinite(l.intensity)) bad("intensity", "is negative or not finite");
        if (!(l.range >= 0.0f) || !std::isfinite(l.range)) bad("range", "is negative or not finite");
        if (l.type == PunctualLight::Type::Spot &&
            !(l.innerConeAngle >= 0.0f && l.innerConeAngle < l.outerConeAngle && l.outerConeAngle <= 1.5707964f))
            bad("outerConeAngle", "must satisfy 0 <= innerConeAngle < outerConeAngle <= pi / 2");
    }
    punctual_ = std::move(lights);
}

// The frame's light: the direction toward it (the headlight's is the view direction), and the punctual lights
// relative to the eye, in float (as the items' matrices).
void Renderer::frameLights(const Camera& camera) {
    lightDir_ = light_.headlight ? vec3(camera.viewDirection()) : glm::normalize(light_.direction);
    const dvec3 eye = camera.eye();
    for (size_t k = 0; k < punctual_.size(); ++k) {
        const PunctualLight& l = punctual_[k];
        const float type = l.type == PunctualLight::Type::Directional ? 0.0f
                           : l.type == PunctualLight::Type::Point     ? 1.0f
                                                                      : 2.0f;
        punctualPos_[k] = vec4(vec3(l.position - eye), type);
        punctualDir_[k] = vec4(glm::normalize(l.direction), l.range);
        punctualE_[k] = l.color * l.intensity;
        // KHR_lights_punctual's cone: clamp(cos * scale + offset), scale = 1 / max(0.001, cos inner - cos outer).
        const float cosOuter = std::cos(l.outerConeAngle), cosInner = std::cos(l.innerConeAngle);
        const float scale = 1.0f / std::max(0.001f, cosInner - cosOuter);
        punctualCone_[k] = vec2(scale, -cosOuter * scale);
    }
}

}  // namespace sg
