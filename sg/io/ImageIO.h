// RGBA8 images: PNG in and out (stb), and the pixel comparison the accuracy harness counts with.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sg {

struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;  // rows top to bottom
};

// Throws std::runtime_error naming the path and the reason.
void savePng(const std::string& path, const Image& img);
Image loadPng(const std::string& path);

// Pixels whose RGB differs by more than `tolerance` in any channel. Throws std::invalid_argument when
// the sizes differ.
size_t countDifferingPixels(const Image& a, const Image& b, int tolerance = 0);
// Mean absolute difference per channel over RGB (0-255 scale): how far an approximate render is from its
// reference. Throws std::invalid_argument when the sizes differ.
double meanAbsoluteError(const Image& a, const Image& b);

}  // namespace sg
