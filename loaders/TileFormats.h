// 3D Tiles' binary tile formats (placeholder interface).
#pragma once
#include "loaders/Gltf.h"
#include "sg/core/Math.h"

#include <string>
#include <vector>

namespace sg::tiles {
enum class ContentKind { Glb, Json, B3dm, I3dm, Cmpt, Pnts, Unknown };
ContentKind sniffContent(const unsigned char* data, size_t size);
struct Bytes {
    const unsigned char* data = nullptr;
    size_t size = 0;
};
struct B3dm {
    Bytes glb;
    bool hasRtcCenter = false;
    dvec3 rtcCenter{0.0};
    uint32_t batchLength = 0;
};
struct I3dm {
    Bytes glb;
    std::string glbUri;
    std::vector<dmat4> instances;
};
struct Cmpt {
    std::vector<Bytes> tiles;
};
B3dm parseB3dm(const std::string& file, const unsigned char* data, size_t size);
I3dm parseI3dm(const std::string& file, const unsigned char* data, size_t size);
Cmpt parseCmpt(const std::string& file, const unsigned char* data, size_t size);
uint32_t pntsPointCount(const std::string& file, const unsigned char* data, size_t size);
}  // namespace sg::tiles
