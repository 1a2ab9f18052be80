// The GPU copies of the meshes and textures a renderer draws: each uploaded on its first use and kept, with a
// reference (so that its pointer stays valid), until the frames stop using it.
// Internal header: not installed (CMakeLists.txt, SGKIT_INTERNAL_HEADERS); its shape may change freely.
#pragma once
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"
#include "sg/core/Ref.h"

#include <cstddef>
#include <cstdint>
#include <unordered_map>

namespace sg {

// A mesh in GL: a vertex array over one vertex buffer (an attribute block each) and an index buffer.
struct GpuMesh {
    ref_ptr<const Mesh> mesh;
    unsigned vao = 0, vbo = 0, ibo = 0;
    unsigned indexType = 0;  // GL_UNSIGNED_SHORT or GL_UNSIGNED_INT
    int indexCount = 0;
    bool normals = false, uvs = false, colors = false;
    uint64_t lastFrame = 0;
};

// Needs the current GL context of its renderer, alive until the cache is destroyed.
class GpuCache {
public:
    // instanceBuffer: the buffer the item attributes are read from (Shaders.h), recorded in every vertex array.
    // maxAnisotropy: the context's limit, 1 for none.
    GpuCache(unsigned instanceBuffer, float maxAnisotropy);
    ~GpuCache();
    GpuCache(const GpuCache&) = delete;
    GpuCache& operator=(const GpuCache&) = delete;

    // Starts a frame: what mesh() and texture() return from now on is what releaseUnused() keeps.
    void nextFrame() { ++frame_; }
    // Uploads on first use. A Mesh changed after its first upload keeps its old copy until released.
    const GpuMesh& mesh(const Mesh* m);
    // The texture's GL name. A texture drawn with an alpha cutoff (cut) has its own copy, with colour bled under
    // its transparent texels (bleedIntoTransparent).
    unsigned texture(const Texture* t, bool cut);

    // Frees the copies the frame since the last nextFrame() did not use; clear() frees all of them.
    void releaseUnused();
    void clear();
    size_t meshCount() const { return meshes_.size(); }
    size_t textureCount() const { return textures_.size() + cutTextures_.size(); }

private:
    struct GpuTexture {
        ref_ptr<const Texture> texture;
        unsigned id = 0;
        uint64_t lastFrame = 0;
    };
    static void destroy(GpuMesh& g);

    unsigned instanceBuffer_;
    float maxAnisotropy_;
    uint64_t frame_ = 0;
    std::unordered_map<const Mesh*, GpuMesh> meshes_;
    std::unordered_map<const Texture*, GpuTexture> textures_, cutTextures_;
};

}  // namespace sg
