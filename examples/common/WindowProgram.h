// WindowProgram: a headless example handing over to its window program. The window draws through the system
// libGL, which must not meet the headless run's OSMesa GL in one process, so it is a program of its own, built
// beside this one.
#pragma once

namespace common {

// Replaces this process by `program` (a file name, looked for beside this executable) with the same arguments.
// Returns only on failure: 1 after saying why on stderr; 2 when `program` is null (built without GLFW), after
// printing `withoutWindow`. `self` names this program in the messages.
int runWindowProgram(char** argv, const char* program, const char* self, const char* withoutWindow);

}  // namespace common
