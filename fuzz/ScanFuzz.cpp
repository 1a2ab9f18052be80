// libFuzzer target for the scan readers (loaders/points/Scan.h): the input is written to a file of its own and opened
// with openScan, so that LAS and PLY are told apart as for a user's file; every point is read, then the reader is
// rewound and read again. Any bytes either read or throw sg::LoadError. Anything else (a crash, a sanitizer report,
// another exception, a hang past -timeout, a leak) is a finding. The seed corpus in fuzz/scan-corpus/ holds a small
// LAS 1.2 of point format 3, a LAS 1.4 of point format 7 and an ascii PLY.
#include "loaders/points/Scan.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

// One file per fuzzing process, rewritten for each input (not named .laz: that name alone is refused), removed at
// exit. A plain array: it must outlive the exit handler, which a static std::string would not.
char gPath[] = "/tmp/sgkit_scan_fuzz_XXXXXX";

const char* inputPath() {
    static const bool made = [] {
        const int fd = ::mkstemp(gPath);
        if (fd < 0) std::abort();
        ::close(fd);
        std::atexit([] { std::remove(gPath); });
        return true;
    }();
    (void)made;
    return gPath;
}

void writeInput(const uint8_t* data, size_t size) {
    std::FILE* f = std::fopen(inputPath(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
}

void readAll(sg::ScanReader& reader) {
    std::vector<sg::ScanPoint> chunk;
    while (reader.read(chunk, 1000) > 0) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    writeInput(data, size);
    try {
        const std::unique_ptr<sg::ScanReader> reader = sg::openScan(inputPath());
        readAll(*reader);
        reader->rewind();
        readAll(*reader);
    } catch (const sg::LoadError&) {
    }
    return 0;
}
