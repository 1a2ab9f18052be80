// The scan formats' readers behind openScan (loaders/points/Scan.h). Internal header (an internal/ folder): not
// installed.
#pragma once
#include "loaders/points/Scan.h"

#include <memory>
#include <string>

namespace sg {

// LAS 1.2-1.4, point formats 0-10 uncompressed (loaders/points/LasRead.cpp).
std::unique_ptr<ScanReader> openLas(const std::string& path);
// PLY: ascii, binary_little_endian, binary_big_endian; a `vertex` element with x, y, z and optional red, green, blue,
// alpha, nx, ny, nz, intensity (loaders/points/PlyRead.cpp).
std::unique_ptr<ScanReader> openPly(const std::string& path);

}  // namespace sg
