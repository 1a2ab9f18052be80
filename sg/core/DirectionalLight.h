// DirectionalLight: the renderer's main light, either the default headlight or a sun; PunctualLight: the lights a
// scene brings (glTF's KHR_lights_punctual), which physical materials also receive.
#pragma once
#include "sg/core/Math.h"

#include <cstdint>

namespace sg {

struct DirectionalLight {
    // The default lights from the eye, both sides alike, colour x (0.35 + 0.65 |n.l|): every view that sets
    // no light draws as it always has. The other fields apply only when this is false.
    bool headlight = true;
    vec3 direction = vec3(0.0f, 0.0f, 1.0f);  // world axes, toward the light (need not be unit)
    vec3 ambient = vec3(0.35f);               // sky and bounce light, scaled by the baked occlusion
    vec3 color = vec3(0.65f);                 // direct light: diffuse n.l and the specular highlight
    // What physical materials (Material::physical) see besides: a sky of `ambient` above and a ground of
    // ambient x groundShare below, along `up` (world axes; glTF files are +Y up, sgkit's scenes +Z), blended by
    // the cosine between the normal (or the reflected view ray) and up. Their direct light is `color` x pi as
    // irradiance, so that a white matte surface facing it shows `color`, as it does under the classic terms.
    vec3 up = vec3(0.0f, 0.0f, 1.0f);
    float groundShare = 0.5f;

    // A sun: light from `direction` on the side of each surface that faces the eye, none on the other.
    static DirectionalLight sun(const vec3& direction, const vec3& ambient, const vec3& color) {
        DirectionalLight l;
        l.headlight = false;
        l.direction = direction;
        l.ambient = ambient;
        l.color = color;
        return l;
    }
};

// A light of glTF's KHR_lights_punctual, in world axes: radiance by the glTF rules (directional: `intensity` lux,
// point and spot: candela, falling off with the square of the distance and to 0 at `range` where it is given; a
// spot's cone from innerConeAngle to outerConeAngle). Only physical materials receive them.
struct PunctualLight {
    enum class Type : uint8_t { Directional, Point, Spot };
    Type type = Type::Point;
    dvec3 position{0.0};                // point and spot
    vec3 direction{0.0f, 0.0f, -1.0f};  // directional and spot: the way the light travels
    vec3 color{1.0f};                   // linear
    float intensity = 1.0f;
    float range = 0.0f;                                         // 0: unlimited
    float innerConeAngle = 0.0f, outerConeAngle = 0.78539816f;  // radians, spot only
};

}  // namespace sg
