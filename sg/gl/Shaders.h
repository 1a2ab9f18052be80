// The renderer's GLSL program: its two shaders' sources and the vertex attributes they read.
// Internal header: not installed (CMakeLists.txt, SGKIT_INTERNAL_HEADERS); its shape may change freely.
#pragma once
#include "sg/core/Math.h"

#include <cstddef>

namespace sg {

extern const char* const kVertexShader;
extern const char* const kFragmentShader;

// Per vertex, from a mesh's buffer (what the Mesh holds).
constexpr unsigned kPositionLocation = 0, kNormalLocation = 1, kUvLocation = 2, kColorLocation = 3;

// Per instance, from the frame's instance buffer: an item's matrix and base colour, at locations 4 to 8.
struct ItemAttributes {
    mat4 model{1.0f};
    vec4 baseColor{1.0f};
};

// In the bound vertex array: turns the item attributes on, one element per instance.
void enableItemAttributes();
// In the bound vertex array: the item attributes read the bound array buffer from its first'th element (GL 3.3
// has no base instance, so a run points them at its own first item).
void pointItemAttributes(size_t first);

}  // namespace sg
