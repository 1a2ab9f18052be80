// KHR_draco_mesh_compression: primitives whose geometry is a Draco stream are decoded before validation,
// into plain buffer views and accessors, so that the validation and the conversion see an ordinary file.
#pragma once
#include <tiny_gltf.h>

#include <cstddef>
#include <string>
#include <vector>

namespace sg::gltf {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
// Decoded bytes (attributes and indices) a file may add; a few kilobytes of Draco can claim gigabytes.
constexpr size_t kMaxDracoBytes = size_t(1) << 30;

// tinygltf 2.7.0 refuses a primitive whose indices accessor has no buffer view, which is how a Draco primitive's
// is written. For a file whose JSON names the extension: its bytes with each such accessor naming the extension's
// buffer view instead (decodeDraco() then points it at the decoded indices); empty when nothing needs changing.
// `data` has passed prevalidate().
std::vector<unsigned char> dracoIndicesForTinygltf(const unsigned char* data, size_t size, bool binary);

// For every primitive with the extension: decodes its buffer view with Draco and writes each attribute the
// extension names, and the triangles, into a buffer added to the model, pointing the primitive's accessors at it
// (their componentType, type and count as the file declares them; the decoded data must agree). The extension is
// then removed from the primitive. Throws LoadError naming
// meshes[i].primitives[j].extensions.KHR_draco_mesh_compression and why for a malformed stream, a missing attribute, a
// count that differs from the accessor's, or more decoded data than kMaxDracoBytes.
void decodeDraco(const std::string& file, tinygltf::Model& model);

}  // namespace sg::gltf
