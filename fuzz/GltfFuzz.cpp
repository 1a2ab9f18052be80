// libFuzzer target for the glTF loader: any bytes either load or throw sg::LoadError. Anything else (a
// crash, a sanitizer report, another exception, a hang past -timeout, a leak) is a finding.
// The seed corpus in fuzz/corpus/ holds small valid files written by sg::saveGltf (.glb and .gltf), one packed by
// gltfpack (quantized, meshopt-compressed) and hand-made ones with sparse accessors, quantized attributes, a skin,
// morph targets, an unused buffer without a URI, and animations (TRS, normalized rotations and weights, cubic splines;
// and KHR_animation_pointer on materials, a light, a camera and a node). Every load also makes the file's occluders
// (GltfLoadOptions::generateOccluders), so that what the loader accepts is what the occluder generator meets.
#include "loaders/gltf/Gltf.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        sg::GltfLoadOptions options;
        options.generateOccluders = true;
        sg::loadGltfFromMemory(size >= 4 && data[0] == 'g' ? "fuzz.glb" : "fuzz.gltf", data, size, options);
    } catch (const sg::LoadError&) {
    }
    return 0;
}
