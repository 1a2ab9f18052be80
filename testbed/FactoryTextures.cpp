#include "testbed/FactoryTextures.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace scenes {

using namespace sg;

namespace {

uint32_t hash3(uint32_t seed, uint32_t x, uint32_t y) {  // a lattice value per (seed, x, y), well mixed
    uint32_t h = seed * 0x9e3779b1u ^ x * 0x85ebca6bu ^ y * 0xc2b2ae35u;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    return h ^ (h >> 16);
}
double unit(uint32_t h) { return double(h >> 8) * (1.0 / 16777216.0); }

// Value noise in [0, 1) on a lattice of `period` cells across the texture, wrapping at the edges: the
// texture repeats without a seam when `size` is a multiple of the cell size.
double noise(uint32_t seed, int size, int period, double x, double y) {
    const double fx = x * period / size, fy = y * period / size;
    const int ix = int(std::floor(fx)), iy = int(std::floor(fy));
    const double tx = fx - ix, ty = fy - iy;
    const double sx = tx * tx * (3.0 - 2.0 * tx), sy = ty * ty * (3.0 - 2.0 * ty);
    auto at = [&](int i, int j) {
        return unit(hash3(seed, uint32_t((i % period + period) % period), uint32_t((j % period + period) % period)));
    };
    const double a = at(ix, iy), b = at(ix + 1, iy), c = at(ix, iy + 1), d = at(ix + 1, iy + 1);
    return (a + (b - a) * sx) * (1.0 - sy) + (c + (d - c) * sx) * sy;
}
// Octaves from `period` up, each twice as fine and half as strong: in [0, 1).
double fbm(uint32_t seed, int size, int period, int octaves, double x, double y) {
    double sum = 0.0, weight = 0.0, w = 1.0;
    for (int o = 0; o < octaves; ++o, period *= 2, w *= 0.5) {
        sum += w * noise(seed + uint32_t(o) * 7919u, size, period, x, y);
        weight += w;
    }
    return sum / weight;
}

uint8_t byte(double v) { return uint8_t(std::clamp(std::lround(v * 255.0), 0L, 255L)); }

struct Canvas {
    int size;
    std::vector<uint8_t> px;
    explicit Canvas(int n) : size(n), px(size_t(n) * size_t(n) * 4, 255) {}
    void set(int i, int j, double r, double g, double b, double a = 1.0) {
        uint8_t* q = &px[(size_t(j) * size_t(size) + size_t(i)) * 4];
        q[0] = byte(r), q[1] = byte(g), q[2] = byte(b), q[3] = byte(a);
    }
    ref_ptr<Texture> texture() { return make<Texture>(size, size, std::move(px)); }
};

}  // namespace

ref_ptr<Texture> factoryWindowTexture() {
    std::vector<uint8_t> px(64 * 64 * 4);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            uint8_t* q = &px[size_t(j * 64 + i) * 4];
            int r = 255, g = 255, b = 255;
            if (j > 1 && (j % 8 == 0 || (i + (j / 8) * 8) % 16 == 0)) r = g = b = 225;
            const bool window = i >= 16 && i < 48 && j >= 19 && j < 51;
            if (window) {
                const bool frame = i == 16 || i == 47 || j == 19 || j == 50 || i == 31 || i == 32 || j == 34;
                if (frame)
                    r = g = b = 235;
                else {
                    r = 70 + (j - 19);
                    g = 95 + (j - 19);
                    b = 120 + (j - 19);
                }
            }
            q[0] = uint8_t(r), q[1] = uint8_t(g), q[2] = uint8_t(b), q[3] = 255;
        }
    return make<Texture>(64, 64, std::move(px));
}

ref_ptr<Texture> factoryBrickTexture(uint32_t seed) {
    constexpr int n = 128, band = 6, course = 4, bricks = 11;  // 11 bricks of ~27 cm and 9 cm courses per 3 m bay
    Canvas c(n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double grain = 0.06 * (unit(hash3(seed, uint32_t(i), uint32_t(j))) - 0.5);
            if (j < band) {  // the concrete band under the eaves of each storey
                const double v = j < 2 ? 1.0 : 0.93 + grain;
                c.set(i, j, v, v, j < 2 ? 1.0 : v * 0.98);
                continue;
            }
            const int row = (j - band) / course;
            const bool bedJoint = (j - band) % course == course - 1;
            // Stretcher bond: each course shifted by half a brick; brick k spans [k n / bricks, (k+1) n / bricks).
            const double x = std::fmod(i + (row % 2) * 0.5 * n / bricks, double(n));
            const int k = int(x * bricks / n);
            const bool headJoint = int((k + 1) * double(n) / bricks - x) == 0;
            if (bedJoint || headJoint) {
                const double v = 0.72 + grain;
                c.set(i, j, v, v * 0.97, v * 0.92);
                continue;
            }
            const double tone = 0.85 + 0.3 * unit(hash3(seed ^ 0xb1u, uint32_t(k), uint32_t(row)));
            const double burn = 0.08 * fbm(seed ^ 0xb2u, n, 8, 2, i, j);
            c.set(i, j, (0.66 - burn) * tone + grain, (0.32 - burn) * tone + grain, (0.24 - burn) * tone + grain);
        }
    // The window of factoryWindowTexture(), twice the texels.
    for (int j = 38; j < 102; ++j)
        for (int i = 32; i < 96; ++i) {
            const int wi = i / 2, wj = j / 2;
            const bool frame = wi == 16 || wi == 47 || wj == 19 || wj == 50 || wi == 31 || wi == 32 || wj == 34;
            if (frame)
                c.set(i, j, 0.92, 0.92, 0.92);
            else
                c.set(i, j, (70 + (wj - 19)) / 255.0, (95 + (wj - 19)) / 255.0, (120 + (wj - 19)) / 255.0);
        }
    return c.texture();
}

ref_ptr<Texture> factoryRoofTexture(uint32_t seed) {
    constexpr int n = 128, rib = 16;  // 8 ribs across 4 m
    Canvas c(n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            // Corrugation: the flat rendering cannot shade the ribs, the texture does.
            const double wave = 0.1 * std::cos(2.0 * M_PI * i / rib);
            const double weather = 0.16 * (fbm(seed, n, 4, 3, i, j) - 0.5);
            const double streak = 0.05 * (noise(seed ^ 0x51u, n, 32, i, j * 0.125) - 0.5);
            const double grain = 0.03 * (unit(hash3(seed, uint32_t(i), uint32_t(j))) - 0.5);
            const double v = 0.82 + wave + weather + streak + grain;
            const double rust = std::max(0.0, fbm(seed ^ 0x52u, n, 4, 2, i, j) - 0.62) * 0.5;
            c.set(i, j, v + rust, v + rust * 0.2, v - rust * 0.6);
        }
    return c.texture();
}

ref_ptr<Texture> factoryGrassTexture(uint32_t seed) {
    constexpr int n = 128;
    Canvas c(n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            // Mostly fine detail: broad blotches would repeat visibly every few metres.
            const double clumps = fbm(seed, n, 4, 2, i, j), tufts = fbm(seed ^ 0x63u, n, 16, 3, i, j);
            const double dry = std::max(0.0, fbm(seed ^ 0x61u, n, 4, 3, i, j) - 0.6) * 0.8;
            const double blade = unit(hash3(seed ^ 0x62u, uint32_t(i), uint32_t(j)));
            const double v = 0.74 + 0.08 * clumps + 0.14 * tufts + 0.12 * (blade - 0.5);
            c.set(i, j, v * (0.92 + dry), v, v * (0.85 - 0.3 * dry));
        }
    return c.texture();
}

ref_ptr<Texture> factoryAsphaltTexture(uint32_t seed) {
    constexpr int n = 128;
    Canvas c(n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double grain = unit(hash3(seed, uint32_t(i), uint32_t(j)));
            const double patch = fbm(seed ^ 0x71u, n, 4, 3, i, j);
            double v = 0.84 + 0.1 * (grain - 0.5) + 0.14 * (patch - 0.5);
            if (grain > 0.985) v += 0.12;                          // a chipping of light stone
            const double tar = std::max(0.0, patch - 0.68) * 0.8;  // darker repairs
            v -= tar;
            c.set(i, j, v, v, v * 1.02);
        }
    return c.texture();
}

ref_ptr<Texture> factoryTreeTexture(uint32_t seed) {
    std::vector<uint8_t> px(64 * 64 * 4, 0);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            uint8_t* q = &px[size_t(j * 64 + i) * 4];
            const double x = (i + 0.5) / 64.0, v = (j + 0.5) / 64.0;  // v = 0 at the crown's top
            const double dx = (x - 0.5) / 0.45, dy = (v - 0.4) / 0.4;
            // Foliage: clumps lit from above, darker inside and below; bark: vertical streaks.
            const double leaf = fbm(seed, 64, 8, 3, i, j), speck = unit(hash3(seed ^ 0x81u, uint32_t(i), uint32_t(j)));
            if (dx * dx + dy * dy < 1.0) {
                const double shade = 0.75 + 0.35 * leaf - 0.25 * std::max(0.0, dy) + 0.1 * (speck - 0.5);
                q[0] = byte(0.22 * shade), q[1] = byte(0.5 * shade), q[2] = byte(0.17 * shade), q[3] = 255;
            } else if (std::abs(x - 0.5) < 0.06 && v > 0.6) {
                const double bark = 0.8 + 0.3 * noise(seed ^ 0x82u, 64, 32, i, j * 0.1);
                q[0] = byte(0.4 * bark), q[1] = byte(0.29 * bark), q[2] = byte(0.18 * bark), q[3] = 255;
            }
        }
    return make<Texture>(64, 64, std::move(px));
}

}  // namespace scenes
