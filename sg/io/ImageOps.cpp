#include "sg/io/ImageOps.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <utility>

namespace sg {

void bleedIntoTransparent(Image& img) {
    const int w = img.width, h = img.height;
    if (w < 0 || h < 0 || img.rgba.size() != size_t(w) * size_t(h) * 4u)
        throw std::invalid_argument("bleedIntoTransparent(): " + std::to_string(img.rgba.size()) + " bytes are not " +
                                    std::to_string(w) + "x" + std::to_string(h) + " RGBA pixels");
    std::vector<uint8_t>& px = img.rgba;
    std::vector<int> ring;
    std::vector<char> filled(size_t(w) * size_t(h));
    for (size_t i = 0; i < filled.size(); ++i) filled[i] = px[i * 4 + 3] != 0;
    auto edge = [&](int x, int y) {
        if (filled[size_t(y) * size_t(w) + size_t(x)]) return false;
        return (x > 0 && filled[size_t(y) * size_t(w) + size_t(x - 1)]) ||
               (x + 1 < w && filled[size_t(y) * size_t(w) + size_t(x + 1)]) ||
               (y > 0 && filled[size_t(y - 1) * size_t(w) + size_t(x)]) ||
               (y + 1 < h && filled[size_t(y + 1) * size_t(w) + size_t(x)]);
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (edge(x, y)) ring.push_back(y * w + x);
    std::vector<int> next;
    std::vector<std::array<uint8_t, 3>> colour;
    while (!ring.empty()) {
        colour.clear();
        for (int i : ring) {
            const int x = i % w, y = i / w;
            int sum[3] = {0, 0, 0}, n = 0;
            for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
                const int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                const size_t j = size_t(ny) * size_t(w) + size_t(nx);
                if (!filled[j]) continue;
                for (int c = 0; c < 3; ++c) sum[c] += px[j * 4 + size_t(c)];
                ++n;
            }
            colour.push_back(
                {uint8_t((sum[0] + n / 2) / n), uint8_t((sum[1] + n / 2) / n), uint8_t((sum[2] + n / 2) / n)});
        }
        for (size_t k = 0; k < ring.size(); ++k) {
            const size_t i = size_t(ring[k]);
            filled[i] = 1;
            for (size_t c = 0; c < 3; ++c) px[i * 4 + c] = colour[k][c];
        }
        next.clear();
        for (int i : ring) {
            const int x = i % w, y = i / w;
            for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
                const int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                const int j = ny * w + nx;
                if (!filled[size_t(j)]) next.push_back(j);
            }
        }
        std::sort(next.begin(), next.end());
        next.erase(std::unique(next.begin(), next.end()), next.end());
        ring.swap(next);
    }
}

}  // namespace sg
