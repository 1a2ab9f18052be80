// PvsTable: per view cell of a grid, the entries of a scene's main flat image hidden from every point of the
// cell (a potentially visible set, stored as its complement), for the cull to drop before any other test.
//
// Cells are the boxes origin + (i, j, k) * cellSize, of nx x ny x nz cells; per cell one bit per image entry,
// set for an entry hidden from everywhere in the cell (its whole subtree is then hidden; bits below it are
// not read). The table is bound to one image: its entry count and a hash of the entries' kinds, subtree
// ends and bounds; any change to those makes it stale. It holds for perspective cameras whose near plane
// lies within [minNear, maxNear] (sg/build/PvsBuilder.h says why).
#pragma once
#include "sg/core/Math.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sg {

struct FlatImage;
class Scene;

class PvsTable {
public:
    struct Grid {
        dvec3 origin{0.0};
        dvec3 cellSize{1.0};
        uint32_t nx = 0, ny = 0, nz = 0;
    };

    PvsTable() = default;
    // Every cell with nothing hidden. Throws std::invalid_argument for an empty or non-finite grid, too
    // many cells, or a near range that is not 0 < minNear <= maxNear.
    PvsTable(const Grid& grid, const FlatImage& img, double minNear, double maxNear);

    // The hash the table is bound to: entry kinds, subtree ends and bounds (not Scene::structureVersion(),
    // which counts rebuilds: a rebuilt but identical scene keeps its table).
    static uint64_t hashImage(const FlatImage& img);

    const Grid& grid() const { return grid_; }
    size_t cellCount() const { return size_t(grid_.nx) * grid_.ny * grid_.nz; }
    uint32_t entryCount() const { return entries_; }
    uint64_t imageHash() const { return hash_; }
    size_t wordsPerCell() const { return words_; }
    double minNear() const { return minNear_; }
    double maxNear() const { return maxNear_; }

    // The cell holding p (on a face between two cells: either), or -1 when p is in none.
    long cellAt(const dvec3& p) const;
    Box cellBox(size_t cell) const;
    // The hidden bits of the eye's cell (entry i: bit i % 64 of word i / 64), or nullptr when the eye is in
    // no cell.
    const uint64_t* hiddenFor(const dvec3& eye) const;
    const uint64_t* hidden(size_t cell) const { return &bits_[cell * words_]; }
    bool isHidden(size_t cell, uint32_t entry) const { return (hidden(cell)[entry >> 6] >> (entry & 63)) & 1u; }
    void setHidden(size_t cell, uint32_t entry);
    size_t hiddenCount(size_t cell) const;  // bits set in the cell

    // Why the table does not fit `scene`'s image (entry count, hash), or empty when it does.
    std::string mismatch(const Scene& scene) const;
    bool matches(const Scene& scene) const { return mismatch(scene).empty(); }

    // Binary file (little-endian): magic, version, sizes, grid, near range, then the bits. Throws
    // std::runtime_error naming the file on an I/O error.
    void save(const std::string& path) const;
    // Validates everything before allocating (truncated, bad magic or version, counts absurd or not
    // matching the file's size, non-finite grid); throws std::runtime_error naming the file and the fault.
    static PvsTable load(const std::string& path);

private:
    Grid grid_;
    uint32_t entries_ = 0;
    uint64_t hash_ = 0;
    size_t words_ = 0;
    double minNear_ = 0.0, maxNear_ = 0.0;
    std::vector<uint64_t> bits_;
};

}  // namespace sg
