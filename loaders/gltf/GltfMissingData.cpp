// Buffers without data in the file (no uri outside a GLB's BIN chunk): glTF allows them, and a file may leave out
// what it does not need everywhere. What reads one is detached before validation and skipped by the conversion.
#include "loaders/gltf/internal/GltfConverter.h"

namespace sg::gltf {

std::vector<bool> detachMissingData(tinygltf::Model& m) {
    // undoNormalizing() has emptied them; every other buffer has at least one byte (glTF: byteLength >= 1).
    std::vector<bool> absent(m.buffers.size());
    bool any = false;
    for (size_t i = 0; i < m.buffers.size(); ++i) {
        absent[i] = m.buffers[i].uri.empty() && m.buffers[i].data.empty();
        any = any || absent[i];
    }
    if (!any) return {};
    auto missing = [&](int view) {
        if (view < 0 || size_t(view) >= m.bufferViews.size()) return false;  // validate() names it
        const int b = m.bufferViews[size_t(view)].buffer;
        return b >= 0 && size_t(b) < absent.size() && absent[size_t(b)];
    };
    std::vector<bool> noData(m.accessors.size());
    for (size_t i = 0; i < m.accessors.size(); ++i) {
        tinygltf::Accessor& a = m.accessors[i];
        const auto& sp = a.sparse;
        if (!missing(a.bufferView) &&
            !(sp.isSparse && (missing(sp.indices.bufferView) || missing(sp.values.bufferView))))
            continue;
        noData[i] = true;  // zeros to any reader: nothing reads past a buffer that is not there
        a.bufferView = -1;
        a.byteOffset = 0;
        a.sparse.isSparse = false;
    }
    for (tinygltf::Image& im : m.images)
        if (missing(im.bufferView)) im.bufferView = -1;  // no bytes: the texture is skipped with a warning
    for (tinygltf::BufferView& v : m.bufferViews)
        if (v.buffer >= 0 && size_t(v.buffer) < absent.size() && absent[size_t(v.buffer)])
            v.byteOffset = v.byteLength = 0;
    return noData;
}

std::string Converter::missingData(const tinygltf::Primitive& p) const {
    auto lacks = [&](int acc) { return acc >= 0 && size_t(acc) < noData.size() && noData[size_t(acc)]; };
    auto why = [&](int acc, const std::string& use) {
        return "accessors[" + std::to_string(acc) + "] (" + use +
               ") has no data: its buffer is not in the file, primitive skipped";
    };
    if (lacks(p.indices)) return why(p.indices, "indices");
    for (const auto& [name, acc] : p.attributes)
        if (lacks(acc)) return why(acc, "attributes." + name);
    for (size_t t = 0; t < p.targets.size(); ++t)
        for (const auto& [name, acc] : p.targets[t])
            if (lacks(acc)) return why(acc, at("targets", t) + "." + name);
    return {};
}

}  // namespace sg::gltf
