#include "sgview/Info.h"

#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace sgview {

using namespace sg;

namespace {

struct Sums {
    uint64_t paths = 0, triangles = 0, points = 0, lines = 0;
};

// The child an LOD shows nearest (distance) or largest (pixel size): its full detail.
size_t finestChild(const LOD& lod) {
    size_t best = 0;
    for (size_t i = 1; i < lod.numChildren(); ++i) {
        const bool finer = lod.mode() == LOD::Mode::Distance ? lod.range(i).min < lod.range(best).min
                                                             : lod.range(i).max > lod.range(best).max;
        if (finer) best = i;
    }
    return best;
}

}  // namespace

SceneInfo computeInfo(const Node& root, const Scene& scene) {
    SceneInfo info;
    std::unordered_map<const Node*, Sums> done;
    std::unordered_set<const Mesh*> meshes;
    std::unordered_set<const Material*> materials;
    std::unordered_set<const Texture*> textures;
    std::vector<std::pair<const Node*, size_t>> stack{{&root, 0}};  // node, next child to visit
    while (!stack.empty()) {
        const Node* n = stack.back().first;
        const size_t next = stack.back().second;
        if (next < n->numChildren()) {
            ++stack.back().second;
            const Node* c = n->child(next);
            if (c && !done.count(c)) stack.emplace_back(c, 0);
            continue;
        }
        stack.pop_back();
        Sums s{1, 0, 0, 0};
        for (size_t i = 0; i < n->numChildren(); ++i) {
            const Node* c = n->child(i);
            if (!c) continue;
            const Sums& cs = done.at(c);
            s.paths += cs.paths;
            const bool shown = n->kind() == NodeKind::LOD      ? i == finestChild(static_cast<const LOD&>(*n))
                               : n->kind() == NodeKind::Switch ? static_cast<const Switch&>(*n).isOn(i)
                                                               : true;
            if (shown) {
                s.triangles += cs.triangles;
                s.points += cs.points;
                s.lines += cs.lines;
            }
        }
        if (n->kind() == NodeKind::Geometry) {
            const auto& g = static_cast<const Geometry&>(*n);
            if (const Mesh* m = g.mesh()) {
                s.triangles += m->triangleCount();
                s.points += m->pointCount();
                s.lines += m->lineCount();
                if (meshes.insert(m).second) info.meshBytes += m->bytes();
            }
            if (const Material* mat = g.material()) {
                materials.insert(mat);
                if (const Texture* t = mat->texture.get(); t && textures.insert(t).second)
                    info.textureBytes += t->rgba().size();
            }
        }
        info.kinds[size_t(n->kind())]++;
        info.nodeBytes += nodeBytes(n->kind());
        done.emplace(n, s);
    }
    const Sums& r = done.at(&root);
    info.nodes = done.size();
    info.paths = r.paths;
    info.triangles = r.triangles;
    info.points = r.points;
    info.lines = r.lines;
    info.meshes = meshes.size();
    info.materials = materials.size();
    info.textures = textures.size();
    info.imageBytes = scene.bytes();
    const FlatImage& img = scene.image();
    info.boundValid = img.size() > 0 && !(img.flags[0] & (FlatImage::kEmpty | FlatImage::kInvalid));
    if (info.boundValid) info.bound = img.box(0);
    return info;
}

void printInfo(std::FILE* out, const std::string& title, const SceneInfo& i, const std::vector<std::string>& warnings) {
    auto size = [](size_t b) {  // "812 B", "12.5 KB", "3.20 MB"
        char buf[32];
        if (b < 1024)
            std::snprintf(buf, sizeof buf, "%zu B", b);
        else if (b < 1024 * 1024)
            std::snprintf(buf, sizeof buf, "%.1f KB", double(b) / 1024.0);
        else
            std::snprintf(buf, sizeof buf, "%.2f MB", double(b) / (1024.0 * 1024.0));
        return std::string(buf);
    };
    std::fprintf(out, "scene: %s\n", title.c_str());
    std::fprintf(out, "nodes: %llu distinct, %llu counted per path\n", (unsigned long long)i.nodes,
                 (unsigned long long)i.paths);
    for (size_t k = 0; k < kNodeKinds; ++k)
        std::fprintf(out, "  %-10s %llu\n", kindName(NodeKind(k)), (unsigned long long)i.kinds[k]);
    std::fprintf(out, "triangles: %llu at full detail, counted per path\n", (unsigned long long)i.triangles);
    if (i.points || i.lines)
        std::fprintf(out, "points: %llu, line segments: %llu, at full detail, counted per path\n",
                     (unsigned long long)i.points, (unsigned long long)i.lines);
    std::fprintf(out, "meshes: %llu, materials: %llu, textures: %llu\n", (unsigned long long)i.meshes,
                 (unsigned long long)i.materials, (unsigned long long)i.textures);
    if (i.boundValid) {
        const dvec3 c = i.bound.center(), e = i.bound.max - i.bound.min;
        // From the flat image: float, rounded outward.
        std::fprintf(out, "bounds: min (%g, %g, %g) max (%g, %g, %g), size (%g, %g, %g), centre (%g, %g, %g)\n",
                     i.bound.min.x, i.bound.min.y, i.bound.min.z, i.bound.max.x, i.bound.max.y, i.bound.max.z, e.x, e.y,
                     e.z, c.x, c.y, c.z);
    } else {
        std::fprintf(out, "bounds: none (nothing to draw, or a geometry with non-finite positions)\n");
    }
    std::fprintf(out, "memory: %s = meshes %s + textures %s + nodes %s + flat image %s\n",
                 size(i.meshBytes + i.textureBytes + i.nodeBytes + i.imageBytes).c_str(), size(i.meshBytes).c_str(),
                 size(i.textureBytes).c_str(), size(i.nodeBytes).c_str(), size(i.imageBytes).c_str());
    std::fprintf(out, "warnings: %zu\n", warnings.size());
    for (const std::string& w : warnings) std::fprintf(out, "  %s\n", w.c_str());
}

}  // namespace sgview
