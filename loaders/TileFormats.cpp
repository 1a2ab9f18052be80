#include "loaders/TileFormats.h"

#include <cstring>

namespace sg::tiles {
ContentKind sniffContent(const unsigned char* d, size_t n) {
    if (n >= 4 && !std::memcmp(d, "glTF", 4)) return ContentKind::Glb;
    if (n >= 4 && !std::memcmp(d, "b3dm", 4)) return ContentKind::B3dm;
    if (n >= 4 && !std::memcmp(d, "i3dm", 4)) return ContentKind::I3dm;
    if (n >= 4 && !std::memcmp(d, "cmpt", 4)) return ContentKind::Cmpt;
    if (n >= 4 && !std::memcmp(d, "pnts", 4)) return ContentKind::Pnts;
    size_t i = 0;
    if (n >= 3 && d[0] == 0xEF && d[1] == 0xBB && d[2] == 0xBF) i = 3;
    while (i < n && (d[i] == ' ' || d[i] == '\n' || d[i] == '\r' || d[i] == '\t')) ++i;
    return i < n && d[i] == '{' ? ContentKind::Json : ContentKind::Unknown;
}
B3dm parseB3dm(const std::string& f, const unsigned char*, size_t) { throw LoadError(f, "", "b3dm: not yet"); }
I3dm parseI3dm(const std::string& f, const unsigned char*, size_t) { throw LoadError(f, "", "i3dm: not yet"); }
Cmpt parseCmpt(const std::string& f, const unsigned char*, size_t) { throw LoadError(f, "", "cmpt: not yet"); }
uint32_t pntsPointCount(const std::string&, const unsigned char*, size_t) { return 0; }
}  // namespace sg::tiles
