#include "sg/io/ImageIO.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cstdlib>
#include <stdexcept>

namespace sg {

void savePng(const std::string& path, const Image& img) {
    if (img.width <= 0 || img.height <= 0 || img.rgba.size() != size_t(img.width) * size_t(img.height) * 4)
        throw std::runtime_error("savePng(): " + path + ": image is empty or its size does not match");
    if (!stbi_write_png(path.c_str(), img.width, img.height, 4, img.rgba.data(), img.width * 4))
        throw std::runtime_error("savePng(): " + path + ": could not write the file");
}

Image loadPng(const std::string& path) {
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 4);
    if (!data)
        throw std::runtime_error("loadPng(): " + path + ": " +
                                 (stbi_failure_reason() ? stbi_failure_reason() : "unreadable"));
    Image img{w, h, std::vector<uint8_t>(data, data + size_t(w) * size_t(h) * 4)};
    stbi_image_free(data);
    return img;
}

namespace {
void checkSameSize(const char* fn, const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height || a.rgba.size() != b.rgba.size())
        throw std::invalid_argument(std::string(fn) + ": sizes differ (" + std::to_string(a.width) + "x" +
                                    std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                    std::to_string(b.height) + ")");
}
}  // namespace

size_t countDifferingPixels(const Image& a, const Image& b, int tol) {
    checkSameSize("countDifferingPixels()", a, b);
    size_t n = 0;
    for (size_t i = 0; i < a.rgba.size(); i += 4) {
        bool differ = false;
        for (int c = 0; c < 3; ++c) differ |= std::abs(int(a.rgba[i + size_t(c)]) - int(b.rgba[i + size_t(c)])) > tol;
        n += differ;
    }
    return n;
}

double meanAbsoluteError(const Image& a, const Image& b) {
    checkSameSize("meanAbsoluteError()", a, b);
    double sum = 0.0;
    for (size_t i = 0; i < a.rgba.size(); i += 4)
        for (size_t c = 0; c < 3; ++c) sum += std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c]));
    const size_t pixels = a.rgba.size() / 4;
    return pixels ? sum / (3.0 * double(pixels)) : 0.0;
}

}  // namespace sg
