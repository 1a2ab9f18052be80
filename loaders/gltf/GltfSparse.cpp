// Sparse accessors: checked against their views, then made dense (a copy of the base, or zeros, with the
// listed elements substituted), so that everything after validation reads plain accessors.
#include "loaders/gltf/internal/GltfDetail.h"

namespace sg::gltf {

namespace {

size_t elementSize(const tinygltf::Accessor& a) {
    return size_t(tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType))) *
           size_t(tinygltf::GetNumComponentsInType(uint32_t(a.type)));
}

uint32_t sparseIndex(const unsigned char* p, int comp, size_t j) {
    if (comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return p[j];
    if (comp == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        uint16_t v;
        std::memcpy(&v, p + 2 * j, 2);
        return v;
    }
    uint32_t v;
    std::memcpy(&v, p + 4 * j, 4);
    return v;
}

// Where `bytes` bytes from `offset` of view `view` start; fails naming `path` when they are not all inside it.
const unsigned char* inView(const std::string& file, const tinygltf::Model& m, const std::string& path, int view,
                            int offset, size_t bytes) {
    if (view < 0 || size_t(view) >= m.bufferViews.size())
        fail(file, path + ".bufferView",
             "bufferView " + std::to_string(view) + " does not exist (" + std::to_string(m.bufferViews.size()) +
                 " bufferViews)");
    if (offset < 0) fail(file, path + ".byteOffset", "byteOffset " + std::to_string(offset) + " is negative");
    const tinygltf::BufferView& v = m.bufferViews[size_t(view)];
    if (size_t(offset) > v.byteLength || bytes > v.byteLength - size_t(offset))
        fail(file, path,
             "byteOffset " + std::to_string(offset) + " + " + std::to_string(bytes) +
                 " bytes is past the end of bufferViews[" + std::to_string(view) + "] (" +
                 std::to_string(v.byteLength) + " bytes)");
    return m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + size_t(offset);
}

}  // namespace

void checkSparse(const std::string& file, const tinygltf::Model& m, size_t i, size_t& denseBytes) {
    const tinygltf::Accessor& a = m.accessors[i];
    const auto& sp = a.sparse;
    const std::string path = at("accessors", i) + ".sparse";
    if (sp.count < 1 || size_t(sp.count) > a.count)
        fail(file, path + ".count",
             "count " + std::to_string(sp.count) + " is not in [1, " + std::to_string(a.count) + "]");
    // The dense copy: bounded whatever the base (an accessor of zeros has no bytes in the file behind it).
    if (a.count > (kMaxExpandedBytes - denseBytes) / elementSize(a))
        fail(file, at("accessors", i) + ".count",
             "sparse accessors of more than " + std::to_string(kMaxExpandedBytes) + " bytes in all");
    denseBytes += a.count * elementSize(a);
    const int comp = sp.indices.componentType;
    if (comp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && comp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        comp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        fail(file, path + ".indices.componentType",
             "componentType " + std::to_string(comp) + " is not an unsigned byte, short or int");
    const size_t n = size_t(sp.count);
    const unsigned char* idx = inView(file, m, path + ".indices", sp.indices.bufferView, sp.indices.byteOffset,
                                      n * size_t(tinygltf::GetComponentSizeInBytes(uint32_t(comp))));
    inView(file, m, path + ".values", sp.values.bufferView, sp.values.byteOffset, n * elementSize(a));
    for (size_t j = 0; j < n; ++j) {
        const uint32_t k = sparseIndex(idx, comp, j);
        if (k >= a.count)
            fail(file, path + ".indices",
                 "index " + std::to_string(k) + " at element " + std::to_string(j) + " is out of range (" +
                     std::to_string(a.count) + " elements)");
        if (j > 0 && k <= sparseIndex(idx, comp, j - 1))
            fail(file, path + ".indices",
                 "index " + std::to_string(k) + " at element " + std::to_string(j) +
                     " does not follow the one before (indices must increase strictly)");
    }
}

void applySparse(tinygltf::Model& m) {
    for (tinygltf::Accessor& a : m.accessors) {
        if (!a.sparse.isSparse) continue;
        const size_t elem = elementSize(a);
        tinygltf::Buffer dense;
        dense.data.assign(a.count * elem, 0);
        if (a.bufferView != -1) {
            const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
            const size_t stride = v.byteStride ? v.byteStride : elem;
            const unsigned char* base = m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
            for (size_t i = 0; i < a.count; ++i) std::memcpy(dense.data.data() + i * elem, base + i * stride, elem);
        }
        const auto& sp = a.sparse;
        auto bytes = [&](int view, int offset) {
            const tinygltf::BufferView& v = m.bufferViews[size_t(view)];
            return m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + size_t(offset);
        };
        const unsigned char* idx = bytes(sp.indices.bufferView, sp.indices.byteOffset);
        const unsigned char* values = bytes(sp.values.bufferView, sp.values.byteOffset);
        for (size_t j = 0; j < size_t(sp.count); ++j)
            std::memcpy(dense.data.data() + sparseIndex(idx, sp.indices.componentType, j) * elem, values + j * elem,
                        elem);
        tinygltf::BufferView view;
        view.buffer = int(m.buffers.size());
        view.byteLength = dense.data.size();
        m.buffers.push_back(std::move(dense));
        a.bufferView = int(m.bufferViews.size());
        m.bufferViews.push_back(view);
        a.byteOffset = 0;
        a.sparse.isSparse = false;
    }
}

}  // namespace sg::gltf
