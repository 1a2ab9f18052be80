// The point tile builder's out-of-core split: a chunk denser than chunkPoints (a count-grid cell near a scanner's
// station holds millions of points) divided by octants, file to file, until each part fits in memory.
#include "loaders/points/internal/PointTilerDetail.h"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace sg::pointtiles {
namespace {

// Points read and buffered at a time (~40 MiB each way).
constexpr size_t kBlockPoints = size_t(1) << 20;

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

// Calls `f` with the file's records a block at a time, in file order.
template <class F>
void forEachBlock(const std::string& file, F&& f) {
    std::unique_ptr<std::FILE, FileCloser> in(std::fopen(file.c_str(), "rb"));
    if (!in) throw std::runtime_error(file + ": cannot be opened: " + std::strerror(errno));
    std::string bytes(kBlockPoints * kRecordBytes, '\0');
    for (;;) {
        const size_t got = std::fread(bytes.data(), 1, bytes.size(), in.get());
        if (got % kRecordBytes != 0) throw std::runtime_error(file + ": ends inside a record");
        if (got > 0) f(decodeRecords(bytes.data(), got / kRecordBytes));
        if (got < bytes.size()) break;
    }
    if (std::ferror(in.get())) throw std::runtime_error(file + ": cannot be read");
}

void split(const Cube& cube, const NodeId& node, const std::string& file, uint64_t count, size_t chunkPoints,
           std::vector<SubChunk>& out) {
    if (count <= chunkPoints || node.level == kMaxLevel) {
        out.push_back({node, file, count});
        return;
    }
    std::array<std::string, 8> files;
    std::array<uint64_t, 8> counts{};
    std::array<std::vector<Point>, 8> buffers;
    size_t buffered = 0;
    for (int i = 0; i < 8; ++i) {
        files[size_t(i)] = file + "." + char('0' + i);
        std::filesystem::remove(files[size_t(i)]);
    }
    const auto flush = [&] {
        for (int i = 0; i < 8; ++i)
            if (!buffers[size_t(i)].empty()) {
                appendRecords(files[size_t(i)], buffers[size_t(i)]);
                std::vector<Point>().swap(buffers[size_t(i)]);  // freed: see distribute()
            }
        buffered = 0;
    };
    forEachBlock(file, [&](const std::vector<Point>& block) {
        for (const Point& p : block) {
            const size_t i = size_t(childOf(cube.cell(p.position), node.level));
            buffers[i].push_back(p);
            ++counts[i];
            if (++buffered == kBlockPoints) flush();
        }
    });
    flush();
    std::filesystem::remove(file);
    for (int i = 0; i < 8; ++i)
        if (counts[size_t(i)] > 0) split(cube, node.child(i), files[size_t(i)], counts[size_t(i)], chunkPoints, out);
}

}  // namespace

std::vector<SubChunk> splitChunk(const Cube& cube, const NodeId& root, const std::string& file, uint64_t count,
                                 size_t chunkPoints) {
    std::vector<SubChunk> out;
    split(cube, root, file, count, chunkPoints, out);
    return out;
}

}  // namespace sg::pointtiles
