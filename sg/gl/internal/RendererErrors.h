// How the renderer's files report errors: GL's error flag checked after a step (debug builds only), and a
// rectangle written as their messages write it.
// Internal header: not installed (the internal/ folder); its shape may change freely.
#pragma once
#include "sg/gl/Renderer.h"

#include <string>

namespace sg {

#ifndef NDEBUG
// Throws std::runtime_error "<fn>: <GL error name> (<code>) <what>" when GL's error flag is set, after clearing it.
void checkGl(const char* fn, const char* what);
// Clears GL's error flag: errors left by the application are not ours to report.
void drainGl();
#else
inline void checkGl(const char*, const char*) {}
inline void drainGl() {}
#endif

// "(x, y, widthxheight)".
std::string describe(const Renderer::Viewport& v);

}  // namespace sg
