// The scan entry points: openScan tells LAS from PLY by the first bytes; loadScan reads a whole scan into a
// Transform at its centre holding one Geometry of points.
#include "loaders/points/Scan.h"

#include "loaders/points/internal/ScanFile.h"
#include "loaders/points/internal/ScanFormats.h"
#include "nodes/Geometry.h"
#include "nodes/Transform.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace sg {
namespace {

// Points read per call while loading: a few megabytes of ScanPoint.
constexpr size_t kChunk = size_t(1) << 16;

// The distance between neighbouring points if `count` points spread evenly over `box`: the largest of the three
// estimates (volume / count)^(1/3), (area / count)^(1/2) over the two largest sides, and length / count. A scan of
// a surface (terrain, a facade) is thinner than its spacing, where the area estimate is the larger; a scan spread
// through a volume is thicker, where the volume estimate is. 0 when the points all coincide.
float estimateSpacing(const Box& box, uint64_t count) {
    if (box.empty() || count == 0) return 0.0f;
    dvec3 e = box.max - box.min;
    std::sort(&e[0], &e[0] + 3);  // ascending: e[2] the longest side
    const double n = double(count);
    const double spacing = std::max({std::cbrt(e[0] * e[1] * e[2] / n), std::sqrt(e[1] * e[2] / n), e[2] / n});
    return float(spacing);
}

// The points' bounds, read through once: for files whose header gives none (PLY).
Box measure(ScanReader& reader, std::vector<ScanPoint>& chunk) {
    Box box;
    while (reader.read(chunk, kChunk) > 0)
        for (const ScanPoint& p : chunk) box.expand(p.position);
    reader.rewind();
    return box;
}

// The kept points in float relative to `centre`, with what the file has besides positions.
struct PointArrays {
    std::vector<vec3> positions, normals;
    std::vector<vec4> colors;
    std::vector<uint16_t> intensities;
    Box box;  // of the kept points, in the file's coordinates
};

// Every point, or `maxPoints` of them spread evenly: point i is kept when i * maxPoints / count passes an integer
// (an accumulator, so that no product overflows).
PointArrays readPoints(ScanReader& reader, const dvec3& centre, uint64_t maxPoints, uint64_t fileBytes) {
    const ScanInfo& info = reader.info();
    const bool thin = maxPoints > 0 && info.count > maxPoints;
    PointArrays a;
    // Room for the points the header promises, but no more than the file can hold (a point takes 4 bytes or more in
    // any format), so that a header that lies does not reserve gigabytes.
    const size_t expect = size_t(std::min<uint64_t>(thin ? maxPoints : info.count, fileBytes / 4));
    a.positions.reserve(expect);
    if (info.hasColor) a.colors.reserve(expect);
    if (info.hasIntensity) a.intensities.reserve(expect);
    if (info.hasNormal) a.normals.reserve(expect);
    std::vector<ScanPoint> chunk;
    uint64_t acc = 0;
    while (reader.read(chunk, kChunk) > 0) {
        for (const ScanPoint& p : chunk) {
            if (thin) {
                acc += maxPoints;
                if (acc < info.count) continue;
                acc -= info.count;
            }
            a.box.expand(p.position);
            a.positions.push_back(vec3(p.position - centre));
            if (info.hasColor) a.colors.push_back(vec4(p.color) / 255.0f);
            if (info.hasIntensity) a.intensities.push_back(p.intensity);
            if (info.hasNormal) a.normals.push_back(p.normal);
        }
    }
    return a;
}

}  // namespace

std::unique_ptr<ScanReader> openScan(const std::string& path) {
    char magic[4] = {};
    {
        const ScanFile file(path);
        if (file.size() < 4) throw LoadError(path, "", "not a scan: " + std::to_string(file.size()) + " bytes");
        file.readAt(0, magic, 4);
    }
    if (std::memcmp(magic, "LASF", 4) == 0) return openLas(path);
    if (std::memcmp(magic, "ply", 3) == 0) return openPly(path);
    throw LoadError(path, "", "not a scan: neither LAS (\"LASF\") nor PLY (\"ply\")");
}

ref_ptr<Node> loadScan(const std::string& path, const ScanLoadOptions& options) {
    const std::unique_ptr<ScanReader> reader = openScan(path);
    const ScanInfo& info = reader->info();
    std::vector<ScanPoint> chunk;
    // Float positions relative to the centre keep a tenth of a millimetre within kilometres, whatever the origin.
    const Box bounds = info.bounds.empty() ? measure(*reader, chunk) : info.bounds;
    const dvec3 centre = bounds.empty() ? dvec3(0.0) : bounds.center();
    std::error_code ec;
    const uint64_t fileBytes = std::filesystem::file_size(path, ec);
    PointArrays a = readPoints(*reader, centre, options.maxPoints, ec ? 0 : fileBytes);
    if (a.positions.empty()) throw LoadError(path, "", "no points");

    auto mesh = make<Mesh>();
    const uint64_t kept = a.positions.size();
    mesh->setPoints(std::move(a.positions), std::move(a.colors), std::move(a.normals));
    if (!a.intensities.empty()) mesh->setIntensities(std::move(a.intensities));
    mesh->setPointSpacing(estimateSpacing(a.box, kept));
    mesh->setSource(MeshSource{path});
    auto material = make<Material>(vec4(1.0f));  // white: the points' own colours show as they are
    material->unlit = !info.hasNormal;           // a point without a normal has nothing to light
    auto transform = make<Transform>();
    transform->setTranslation(centre);
    transform->addChild(make<Geometry>(std::move(mesh), std::move(material)));
    return transform;
}

}  // namespace sg
