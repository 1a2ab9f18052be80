// DirectionalLight: the one light the renderer shades with, either the default headlight or a sun.
#pragma once
#include "sg/core/Math.h"

namespace sg {

struct DirectionalLight {
    // The default lights from the eye, both sides alike, colour x (0.35 + 0.65 |n.l|): every view that sets
    // no light draws as it always has. The other fields apply only when this is false.
    bool headlight = true;
    vec3 direction = vec3(0.0f, 0.0f, 1.0f);  // world axes, toward the light (need not be unit)
    vec3 ambient = vec3(0.35f);               // sky and bounce light, scaled by the baked occlusion
    vec3 color = vec3(0.65f);                 // direct light: diffuse n.l and the specular highlight

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

}  // namespace sg
