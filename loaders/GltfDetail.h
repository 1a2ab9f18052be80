// The glTF loader's internal pieces (not installed): raw-byte checks, model validation, conversion to a
// graph, and the names of sgkit's keys in glTF `extras`, shared by the reader and the writer.
#pragma once
#include "loaders/Gltf.h"

#include <tiny_gltf.h>

#include <chrono>
#include <string>

namespace sg::gltf {

// Node extras live under this key: {"sgkit": {"kind": "LOD", ...}}.
constexpr const char* kExtrasKey = "sgkit";
// Deeper JSON is rejected before tinygltf parses it (its extras parser recurses once per level).
constexpr int kMaxJsonDepth = 64;
// Deeper node hierarchies are rejected (the conversion recurses once per level).
constexpr int kMaxNodeDepth = 1000;
// A graph whose paths (shared nodes counted once per path, as a Scene's image holds them) exceed this is refused.
constexpr uint64_t kMaxExpandedNodes = uint64_t(1) << 26;
// Accessors without a buffer view (zeros) may not have more elements than this.
constexpr size_t kMaxZeroAccessor = size_t(1) << 24;
// Images larger than this are not decoded (a small file may claim a huge image).
constexpr long long kMaxImagePixels = 1ll << 26;

// "nodes[3]"
std::string at(const std::string& array, size_t i);
[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& reason);

// Refuses JSON text nested deeper than kMaxJsonDepth (strings skipped), before a parser that recurses sees it.
void checkJsonDepth(const std::string& file, const unsigned char* data, size_t size);

// Checks on the bytes before tinygltf sees them: a GLB's header and chunk lengths (tinygltf 2.7.0 reads
// up to 8 bytes past a BIN chunk that claims more than the file holds) and the JSON's nesting depth.
void prevalidate(const std::string& file, const unsigned char* data, size_t size, bool binary);

// What tinygltf does not check and the conversion relies on: every index in range, accessors inside their
// buffer views and views inside their buffers, strides, counts and types, finite node matrices, the node
// hierarchy a forest (no cycle, no node with two parents), required extensions supported.
void validate(const std::string& file, const tinygltf::Model& model);

// Reports progress once a load has run for options.progressAfterSeconds, at most ten times a second.
class Progress {
public:
    explicit Progress(const GltfLoadOptions& o) : opt_(o), start_(std::chrono::steady_clock::now()) {}
    void report(double fraction, const char* stage);

private:
    const GltfLoadOptions& opt_;
    std::chrono::steady_clock::time_point start_;
    double last_ = -1.0;
};

// Works out Mesh::closed() for every mesh below root (each once) on a loader's thread, so that a page's first draw
// does not (loadGltfPage, the tileset's loads).
void workOutSolids(const Node& root);

// Builds the graph of the default scene (validated model); per-element problems that do not stop the
// load (points, lines, undecodable images) become warnings.
GltfScene convert(const std::string& file, const tinygltf::Model& model, Progress& progress,
                  std::vector<std::string> warnings);

}  // namespace sg::gltf
