// libFuzzer target for the 3D Tiles binary formats (loaders/TileFormats.h): any bytes either parse or throw
// sg::LoadError. Anything else (a crash, a sanitizer report, another exception, a hang past -timeout, a leak) is a
// finding. The seed corpus in fuzz/tiles-corpus/ holds small valid b3dm, i3dm, cmpt and pnts tiles.
#include "loaders/TileFormats.h"

#include <cstddef>
#include <cstdint>

namespace {

void parse(const unsigned char* data, size_t size) {
    using namespace sg::tiles;
    try {
        switch (sniffContent(data, size)) {
            case ContentKind::B3dm: parseB3dm("fuzz.b3dm", data, size); break;
            case ContentKind::I3dm: parseI3dm("fuzz.i3dm", data, size); break;
            case ContentKind::Pnts: pntsPointCount("fuzz.pnts", data, size); break;
            case ContentKind::Cmpt:
                // The inner tiles as the tileset reader would take them.
                for (const Bytes& tile : parseCmpt("fuzz.cmpt", data, size).tiles) parse(tile.data, tile.size);
                break;
            default: break;
        }
    } catch (const sg::LoadError&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    parse(data, size);
    return 0;
}
