// sgview --info: what a scene holds (nodes by kind, triangles, bounds, memory) and what its loader warned.
#pragma once
#include "sg/core/Node.h"
#include "sg/scene/Scene.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace sgview {

constexpr size_t kNodeKinds = size_t(sg::NodeKind::PagedLOD) + 1;  // the last kind

struct SceneInfo {
    std::array<uint64_t, kNodeKinds> kinds{};  // distinct nodes of each kind (a shared node counts once)
    uint64_t nodes = 0;                        // distinct nodes
    uint64_t paths = 0;                        // nodes counted once per path from the root (as drawn)
    uint64_t triangles = 0;  // at full detail (each LOD's finest child, each Switch's children that are on), per path
    uint64_t points = 0, lines = 0;                    // points and line segments, counted as the triangles
    uint64_t meshes = 0, materials = 0, textures = 0;  // distinct
    size_t meshBytes = 0, textureBytes = 0, nodeBytes = 0, imageBytes = 0;
    sg::Box bound;
    bool boundValid = false;
};

// Walks the graph once (iteratively: deep graphs do not exhaust the stack); `scene` must be updated.
SceneInfo computeInfo(const sg::Node& root, const sg::Scene& scene);
void printInfo(std::FILE* out, const std::string& title, const SceneInfo& info,
               const std::vector<std::string>& warnings);

}  // namespace sgview
