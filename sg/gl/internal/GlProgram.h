// The shader program of a vertex and a fragment shader (and optionally a geometry shader), compiled and linked in the
// current OpenGL 3.3 context: the renderer's, and any overlay an application draws beside it.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once

namespace sg {

// Returns the program's GL name. Throws std::runtime_error starting with `who` and carrying GL's log when a
// shader does not compile or the program does not link (nothing is left allocated then). geometrySource: null for none.
unsigned buildGlProgram(const char* vertexSource, const char* fragmentSource, const char* who,
                        const char* geometrySource = nullptr);

}  // namespace sg
