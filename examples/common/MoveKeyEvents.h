// MoveKeyEvents: GLFW key events as the navigator's held movement keys, for every windowed example alike.
#pragma once
#include "common/Navigator.h"

#include <GLFW/glfw3.h>

namespace common {

// W S A D forward, back, left, right; Q E down, up; shift fast. Returns false for any other key.
inline bool setMoveKey(MoveKeys& keys, int glfwKey, bool down) {
    switch (glfwKey) {
        case GLFW_KEY_W: keys.forward = down; return true;
        case GLFW_KEY_S: keys.back = down; return true;
        case GLFW_KEY_A: keys.left = down; return true;
        case GLFW_KEY_D: keys.right = down; return true;
        case GLFW_KEY_Q: keys.down = down; return true;
        case GLFW_KEY_E: keys.up = down; return true;
        case GLFW_KEY_LEFT_SHIFT:
        case GLFW_KEY_RIGHT_SHIFT: keys.fast = down; return true;
        default: return false;
    }
}

}  // namespace common
