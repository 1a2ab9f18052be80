// libFuzzer target for what a 3D Tiles reader parses from outside: the binary formats
// (loaders/tiles/internal/TileFormats.h), tileset.json and subtree files (loaders/tiles/internal/TilesetTable.h), read
// as local and as remote documents (the origin rule), and data: URIs (loaders/net/Resource.h): any bytes either parse
// or throw sg::LoadError. Anything else (a crash, a sanitizer report, another exception, a hang past -timeout, a leak)
// is a finding. The seed corpus in fuzz/tiles-corpus/ holds small valid b3dm, i3dm, cmpt and pnts tiles (b3dm and
// i3dm with batch tables, one with a hierarchy; a pnts with quantized positions, colours, oct normals and batch ids),
// tilesets (one with a schema and tile, content, group and tileset metadata) and subtrees (one with tile metadata, as
// writeTileset writes implicit tiling).
#include "loaders/net/Resource.h"
#include "loaders/tiles/internal/BatchTable.h"
#include "loaders/tiles/internal/Pnts.h"
#include "loaders/tiles/internal/TileFormats.h"
#include "loaders/tiles/internal/TilesetTable.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace {

void subtree(const std::vector<unsigned char>& bytes) {
    using sg::tiles::SemanticProperty;
    sg::tiles::ImplicitTiling t;
    t.subtreeLevels = 3;
    t.availableLevels = 6;
    t.contents = {"c"};
    // Tile metadata classes as writeTileset's schema declares them ("tile"), and others the reader takes.
    t.schema["tile"].box = SemanticProperty{"boundingBox", true, 12};
    t.schema["tile"].error = SemanticProperty{"geometricError", true, 1};
    t.schema["tile32"].sphere = SemanticProperty{"sphere", false, 4};
    t.schema["tile32"].error = SemanticProperty{"error", false, 1};
    t.schema["region"].region = SemanticProperty{"region", true, 6};
    try {
        sg::tiles::parseSubtree("fuzz.subtree", bytes, t, [](const std::string&) {
            return std::vector<unsigned char>(16, 0xff);  // an external buffer: no files read while fuzzing
        });
    } catch (const sg::LoadError&) {
    }
}

void parse(const unsigned char* data, size_t size) {
    using namespace sg::tiles;
    std::vector<std::string> warnings;
    try {
        switch (sniffContent(data, size)) {
            case ContentKind::B3dm: {  // and its batch table, as the tileset reader takes it
                const B3dm b = parseB3dm("fuzz.b3dm", data, size);
                readBatchTable("fuzz.b3dm", b.batchJson, b.batchBinary, b.batchLength, warnings);
                break;
            }
            case ContentKind::I3dm: {
                const I3dm in = parseI3dm("fuzz.i3dm", data, size);
                readBatchTable("fuzz.i3dm", in.batchJson, in.batchBinary, uint32_t(in.instances.size()), warnings);
                break;
            }
            case ContentKind::Pnts:  // its semantics, Draco stream and batch table, as the tileset reader takes it
                readPnts("fuzz.pnts", data, size, warnings);
                break;
            case ContentKind::Cmpt:
                // The inner tiles as the tileset reader would take them.
                for (const Bytes& tile : parseCmpt("fuzz.cmpt", data, size).tiles) parse(tile.data, tile.size);
                break;
            case ContentKind::Json: {  // a tileset, or a JSON subtree of a quadtree of 3 levels
                sg::TilesetOptions options;
                // A schemaUri names a file or URL: refused unread.
                static const std::atomic<bool> cancelled{true};
                options.resource.maxBytes = 0;
                options.resource.cancel = &cancelled;
                const std::vector<unsigned char> bytes(data, data + size);
                for (const char* name : {"fuzz.json", "https://fuzz.test/a/fuzz.json"}) {
                    try {
                        TilesetState(options).addTileset(name, bytes, -1, -1);
                    } catch (const sg::LoadError&) {
                    }
                }
                subtree(bytes);
                break;
            }
            default:
                if (size >= 4 && data[0] == 's') subtree(std::vector<unsigned char>(data, data + size));
                if (size >= 5 && std::memcmp(data, "data:", 5) == 0)
                    sg::readResource(std::string(reinterpret_cast<const char*>(data), size));
                break;
        }
    } catch (const sg::LoadError&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    parse(data, size);
    return 0;
}
