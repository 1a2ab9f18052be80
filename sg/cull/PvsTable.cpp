#include "sg/cull/PvsTable.h"

#include "sg/scene/Scene.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace sg {

namespace {
constexpr char kMagic[8] = {'S', 'G', 'K', 'P', 'V', 'S', '\r', '\n'};  // CR LF: text-mode damage shows
constexpr uint32_t kVersion = 1;
constexpr uint64_t kMaxCells = uint64_t(1) << 24;
constexpr uint64_t kMaxEntries = uint64_t(1) << 31;
// magic, version, entries, hash, nx ny nz, origin, cell size, near range, words per cell
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8 + 12 + 24 + 24 + 16 + 8;

bool validGrid(const PvsTable::Grid& g) {
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(g.origin[a]) || !(g.cellSize[a] > 0.0) || !std::isfinite(g.cellSize[a])) return false;
    return g.nx > 0 && g.ny > 0 && g.nz > 0;
}

void fnv(uint64_t& h, const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 1099511628211ull;
}

// Little-endian fields in and out (the byte order of every host the toolkit builds on).
struct Writer {
    std::string buf;
    template <class T>
    void put(const T& v) {
        buf.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
};
struct Reader {
    const std::string& buf;
    size_t at = 0;
    template <class T>
    T get() {
        T v;
        std::memcpy(&v, buf.data() + at, sizeof v);
        at += sizeof v;
        return v;
    }
};
}  // namespace

PvsTable::PvsTable(const Grid& grid, const FlatImage& img, double minNear, double maxNear)
    : grid_(grid),
      entries_(uint32_t(img.size())),
      hash_(hashImage(img)),
      words_((img.size() + 63) / 64),
      minNear_(minNear),
      maxNear_(maxNear) {
    if (!validGrid(grid) || uint64_t(grid.nx) * grid.ny * grid.nz > kMaxCells)
        throw std::invalid_argument(
            "PvsTable::PvsTable(): the grid must be finite, with positive cell sizes and 1 to " +
            std::to_string(kMaxCells) + " cells");
    if (!(minNear > 0.0 && minNear <= maxNear && std::isfinite(maxNear)))
        throw std::invalid_argument("PvsTable::PvsTable(): the near range [" + std::to_string(minNear) + ", " +
                                    std::to_string(maxNear) + "] is not 0 < min <= max");
    if (img.size() >= kMaxEntries) throw std::invalid_argument("PvsTable::PvsTable(): the image is too large");
    bits_.assign(cellCount() * words_, 0);
}

uint64_t PvsTable::hashImage(const FlatImage& img) {
    uint64_t h = 14695981039346656037ull;
    const size_t n = img.size();
    fnv(h, &n, sizeof n);
    fnv(h, img.kind.data(), n * sizeof(NodeKind));
    fnv(h, img.end.data(), n * sizeof(uint32_t));
    for (const std::vector<float>* col : {&img.cx, &img.cy, &img.cz, &img.ex, &img.ey, &img.ez})
        fnv(h, col->data(), n * sizeof(float));
    fnv(h, &img.origin, sizeof img.origin);
    return h;
}

long PvsTable::cellAt(const dvec3& p) const {
    const uint32_t n[3] = {grid_.nx, grid_.ny, grid_.nz};
    long idx[3];
    for (int a = 0; a < 3; ++a) {
        const double f = (p[a] - grid_.origin[a]) / grid_.cellSize[a];
        if (!(f >= 0.0 && f <= double(n[a]))) return -1;  // NaN too
        idx[a] = std::min(long(f), long(n[a]) - 1);
    }
    return idx[0] + long(grid_.nx) * (idx[1] + long(grid_.ny) * idx[2]);
}

Box PvsTable::cellBox(size_t cell) const {
    SG_ASSERT(cell < cellCount(), "PvsTable::cellBox(): cell past the grid");
    const dvec3 ijk(double(cell % grid_.nx), double((cell / grid_.nx) % grid_.ny),
                    double(cell / (size_t(grid_.nx) * grid_.ny)));
    const dvec3 lo = grid_.origin + ijk * grid_.cellSize;
    return Box{lo, grid_.origin + (ijk + 1.0) * grid_.cellSize};
}

const uint64_t* PvsTable::hiddenFor(const dvec3& eye) const {
    const long c = cellAt(eye);
    return c < 0 || words_ == 0 ? nullptr : hidden(size_t(c));
}

void PvsTable::setHidden(size_t cell, uint32_t entry) {
    SG_ASSERT(cell < cellCount() && entry < entries_, "PvsTable::setHidden(): cell or entry out of range");
    bits_[cell * words_ + (entry >> 6)] |= uint64_t(1) << (entry & 63);
}

size_t PvsTable::hiddenCount(size_t cell) const {
    size_t n = 0;
    for (size_t w = 0; w < words_; ++w) n += size_t(__builtin_popcountll(hidden(cell)[w]));
    return n;
}

std::string PvsTable::mismatch(const Scene& scene) const {
    const FlatImage& img = scene.image();
    if (img.size() != entries_)
        return "the table was built for " + std::to_string(entries_) + " image entries, the scene has " +
               std::to_string(img.size());
    if (hashImage(img) != hash_) return "the scene's entries (kinds or bounds) differ from the ones it was built for";
    return {};
}

void PvsTable::save(const std::string& path) const {
    Writer w;
    w.buf.append(kMagic, sizeof kMagic);
    w.put(kVersion);
    w.put(entries_);
    w.put(hash_);
    w.put(grid_.nx);
    w.put(grid_.ny);
    w.put(grid_.nz);
    for (int a = 0; a < 3; ++a) w.put(grid_.origin[a]);
    for (int a = 0; a < 3; ++a) w.put(grid_.cellSize[a]);
    w.put(minNear_);
    w.put(maxNear_);
    w.put(uint64_t(words_));
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(w.buf.data(), std::streamsize(w.buf.size()));
    f.write(reinterpret_cast<const char*>(bits_.data()), std::streamsize(bits_.size() * sizeof(uint64_t)));
    if (!f) throw std::runtime_error("PvsTable::save(): cannot write " + path);
}

PvsTable PvsTable::load(const std::string& path) {
    auto fail = [&](const std::string& what) { throw std::runtime_error("PvsTable::load(): " + path + ": " + what); };
    std::ifstream f(path, std::ios::binary | std::ios::ate);
    if (!f) fail("cannot be opened");
    const std::streamoff size = f.tellg();
    if (size < std::streamoff(kHeaderBytes))
        fail("truncated: " + std::to_string(size) + " bytes, less than the " + std::to_string(kHeaderBytes) +
             "-byte header");
    std::string head(kHeaderBytes, '\0');
    f.seekg(0);
    f.read(&head[0], std::streamsize(kHeaderBytes));
    if (!f) fail("cannot read the header");
    if (std::memcmp(head.data(), kMagic, sizeof kMagic) != 0) fail("bad magic: not a PVS table");
    Reader r{head, sizeof kMagic};
    const uint32_t version = r.get<uint32_t>();
    if (version != kVersion)
        fail("version " + std::to_string(version) + ", this build reads " + std::to_string(kVersion));
    PvsTable t;
    t.entries_ = r.get<uint32_t>();
    t.hash_ = r.get<uint64_t>();
    t.grid_.nx = r.get<uint32_t>();
    t.grid_.ny = r.get<uint32_t>();
    t.grid_.nz = r.get<uint32_t>();
    for (int a = 0; a < 3; ++a) t.grid_.origin[a] = r.get<double>();
    for (int a = 0; a < 3; ++a) t.grid_.cellSize[a] = r.get<double>();
    t.minNear_ = r.get<double>();
    t.maxNear_ = r.get<double>();
    const uint64_t words = r.get<uint64_t>();
    if (!validGrid(t.grid_)) fail("the grid is empty, not finite or has a cell size <= 0");
    const uint64_t cells = uint64_t(t.grid_.nx) * t.grid_.ny * t.grid_.nz;  // < 2^96 cannot overflow: each < 2^32
    if (t.grid_.nx > kMaxCells || t.grid_.ny > kMaxCells || t.grid_.nz > kMaxCells || cells > kMaxCells)
        fail("absurd cell counts " + std::to_string(t.grid_.nx) + " x " + std::to_string(t.grid_.ny) + " x " +
             std::to_string(t.grid_.nz) + " (at most " + std::to_string(kMaxCells) + " cells)");
    if (uint64_t(t.entries_) >= kMaxEntries) fail("absurd entry count " + std::to_string(t.entries_));
    if (words != (uint64_t(t.entries_) + 63) / 64)
        fail(std::to_string(words) + " words per cell do not match " + std::to_string(t.entries_) + " entries");
    if (!(t.minNear_ > 0.0 && t.minNear_ <= t.maxNear_ && std::isfinite(t.maxNear_))) fail("bad near range");
    // Both factors are bounded above: no overflow. Sizes are checked before anything is allocated.
    const uint64_t body = cells * words * sizeof(uint64_t);
    if (uint64_t(size) != kHeaderBytes + body)
        fail(std::string(uint64_t(size) < kHeaderBytes + body ? "truncated" : "trailing bytes") + ": " +
             std::to_string(size) + " bytes, the sizes give " + std::to_string(kHeaderBytes + body));
    t.words_ = size_t(words);
    t.bits_.resize(size_t(cells * words));
    f.read(reinterpret_cast<char*>(t.bits_.data()), std::streamsize(body));
    if (!f) fail("cannot read the bits");
    // Bits past the last entry must be clear: a set one would name an entry that does not exist.
    if (t.entries_ % 64)
        for (size_t c = 0; c < cells; ++c)
            if (t.bits_[c * words + words - 1] >> (t.entries_ % 64)) fail("bits set past the last entry");
    return t;
}

}  // namespace sg
