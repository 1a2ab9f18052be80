// keepFreedMemory: the process-wide malloc setting for a program that draws with a software rasterizer.
#pragma once

namespace sg {

// A software rasterizer (Renderer::softwareRasterizer()) allocates its binned scene afresh every frame and frees
// it after; glibc hands the freed top of its heap back to the system, and the next frame faults every page in
// again (what that costs: docs/benchmarks.md, "Factory walkthrough"). This keeps freed memory, up to 256 MB, for the
// next frame (glibc's trim threshold and top pad; nothing elsewhere). It changes the whole process, so the program
// decides: a frame loop calls it once its renderer says it rasterizes in software. Calls after the first do nothing. A
// program that wants the memory back calls malloc_trim(0), as sgmap does when it leaves a level.
void keepFreedMemory();

}  // namespace sg
