// The meshopt decoding that fills the views of buffers packers leave without data (EXT_meshopt_compression's
// fallback) from the compressed buffer, before tinygltf's model is validated.
#include "loaders/gltf/internal/GltfDetail.h"

#include <meshoptimizer.h>

#include <cmath>

namespace sg::gltf {

namespace {

struct MeshoptView {
    const std::string& file;
    const std::string path;
    const tinygltf::Value& x;

    [[noreturn]] void bad(const std::string& key, const std::string& why) const {
        fail(file, key.empty() ? path : path + "." + key, why);
    }
    size_t integer(const char* key, bool required, size_t def = 0) const {
        if (!x.Has(key)) {
            if (required) bad(key, "is missing");
            return def;
        }
        const tinygltf::Value& v = x.Get(key);
        const double d = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
        if (!(d >= 0.0 && d <= 9007199254740992.0 && d == std::floor(d))) bad(key, "must be an integer of at least 0");
        return size_t(d);
    }
    std::string string(const char* key, const char* def) const {
        if (!x.Has(key)) return def;
        if (!x.Get(key).IsString()) bad(key, "must be a string");
        return x.Get(key).Get<std::string>();
    }
};

}  // namespace

void decodeMeshopt(const std::string& file, tinygltf::Model& m) {
    size_t decoded = 0;
    for (size_t i = 0; i < m.bufferViews.size(); ++i) {
        tinygltf::BufferView& view = m.bufferViews[i];
        auto ext = view.extensions.find("EXT_meshopt_compression");
        if (ext == view.extensions.end()) ext = view.extensions.find("KHR_meshopt_compression");
        if (ext == view.extensions.end()) continue;
        const MeshoptView mv{file, at("bufferViews", i) + ".extensions." + ext->first, ext->second};
        if (!ext->second.IsObject()) mv.bad("", "must be an object");
        const size_t buffer = mv.integer("buffer", true), offset = mv.integer("byteOffset", false),
                     length = mv.integer("byteLength", true), stride = mv.integer("byteStride", true),
                     count = mv.integer("count", true);
        const std::string mode = mv.string("mode", ""), filter = mv.string("filter", "NONE");
        if (buffer >= m.buffers.size())
            mv.bad("buffer", "buffer " + std::to_string(buffer) + " does not exist (" +
                                 std::to_string(m.buffers.size()) + " buffers)");
        const std::vector<unsigned char>& src = m.buffers[buffer].data;
        if (offset > src.size() || length > src.size() - offset)
            mv.bad("", "byteOffset " + std::to_string(offset) + " + byteLength " + std::to_string(length) +
                           " is past the end of buffer " + std::to_string(buffer) + " (" + std::to_string(src.size()) +
                           " bytes)");
        const bool attributes = mode == "ATTRIBUTES", triangles = mode == "TRIANGLES";
        if (!attributes && !triangles && mode != "INDICES")
            mv.bad("mode", "mode '" + mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
        // meshoptimizer asserts on these rather than returning an error: checked first.
        if (attributes ? (stride < 4 || stride > 256 || stride % 4 != 0) : (stride != 2 && stride != 4))
            mv.bad("byteStride", "byteStride " + std::to_string(stride) + " is not allowed for mode " + mode);
        if (triangles && count % 3 != 0)
            mv.bad("count", "count " + std::to_string(count) + " is not a multiple of 3 (mode TRIANGLES)");
        const bool filterOk =
            filter == "NONE" || (attributes && ((filter == "OCTAHEDRAL" && stride <= 8) ||
                                                (filter == "QUATERNION" && stride == 8) || filter == "EXPONENTIAL"));
        if (!filterOk)
            mv.bad("filter", "filter '" + filter + "' is not supported with mode " + mode + " and byteStride " +
                                 std::to_string(stride));
        if (count > kMaxExpandedBytes / stride || count * stride > view.byteLength)
            mv.bad("count", std::to_string(count) + " elements of " + std::to_string(stride) +
                                " bytes do not fit the view's byteLength " + std::to_string(view.byteLength) +
                                " or are more than " + std::to_string(kMaxExpandedBytes) + " bytes");
        if (view.byteLength > kMaxExpandedBytes - decoded)
            mv.bad("", "decoded buffer views of more than " + std::to_string(kMaxExpandedBytes) + " bytes in all");
        decoded += view.byteLength;

        tinygltf::Buffer out;
        out.data.assign(view.byteLength, 0);
        const unsigned char* in = src.data() + offset;
        const int r = attributes  ? meshopt_decodeVertexBuffer(out.data.data(), count, stride, in, length)
                      : triangles ? meshopt_decodeIndexBuffer(out.data.data(), count, stride, in, length)
                                  : meshopt_decodeIndexSequence(out.data.data(), count, stride, in, length);
        if (r == -1 && length > 0)  // the first byte is 0xa0 (vertex) or 0xe0 (index) plus the codec version
            mv.bad("", "compressed data does not decode (codec version " + std::to_string(in[0] & 0x0f) +
                           " is not one meshoptimizer " + std::to_string(MESHOPTIMIZER_VERSION / 1000) + "." +
                           std::to_string(MESHOPTIMIZER_VERSION % 1000 / 10) + " reads)");
        if (r != 0)
            mv.bad("", "compressed data does not decode (malformed, or not " + std::to_string(count) + " elements)");
        if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data.data(), count, stride);
        if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data.data(), count, stride);
        if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data.data(), count, stride);
        view.buffer = int(m.buffers.size());
        view.byteOffset = 0;
        view.extensions.erase(ext);
        m.buffers.push_back(std::move(out));
    }
}

}  // namespace sg::gltf
