#include "sg/build/VertexLightBaker.h"

#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/MeshBvh.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace sg {

namespace {

uint64_t mix64(uint64_t x) {  // splitmix64 finaliser: decorrelates neighbouring seeds
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

double unit(uint64_t h) { return double(h >> 11) * 0x1.0p-53; }

// Any unit vector perpendicular to n, and a second one completing the frame.
void frame(const dvec3& n, dvec3& t, dvec3& b) {
    t = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, dvec3(1, 0, 0)) : glm::cross(n, dvec3(0, 1, 0)));
    b = glm::cross(n, t);
}

struct Fnv {
    uint64_t h = 0xcbf29ce484222325ull;
    void bytes(const void* p, size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        for (size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 0x100000001b3ull;
    }
    template <class T>
    void pod(const T& v) {
        bytes(&v, sizeof(T));
    }
};

uint64_t inputHash(const std::vector<BakeTarget>& targets, const VertexLightParams& p, uint64_t key) {
    Fnv f;
    f.pod(key);
    f.pod(VertexLightBaker::kVersion);
    f.pod(p.sunDirection);
    f.pod(p.sunAngularRadius);
    f.pod(p.sunSamples);
    f.pod(p.aoSamples);
    f.pod(p.aoDistance);
    f.pod(p.sunDistance);
    f.pod(p.offset);
    f.pod(p.insetFraction);
    f.pod(p.insetMax);
    f.pod(p.query.traversalMask);
    f.pod(p.query.lod);
    for (const BakeTarget& t : targets) {
        const uint64_t n = t.mesh->positions().size();
        f.pod(n);
        f.pod(t.world);
        f.bytes(t.mesh->colors().data(), t.mesh->colors().size() * sizeof(vec4));
    }
    return f.h;
}

constexpr char kMagic[8] = {'S', 'G', 'V', 'L', 'I', 'G', 'H', 'T'};

bool readCache(const std::string& path, uint64_t hash, const std::vector<BakeTarget>& targets,
               std::vector<std::vector<vec4>>& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    char magic[8];
    uint32_t version = 0;
    uint64_t h = 0, count = 0;
    in.read(magic, 8);
    in.read(reinterpret_cast<char*>(&version), sizeof version);
    in.read(reinterpret_cast<char*>(&h), sizeof h);
    in.read(reinterpret_cast<char*>(&count), sizeof count);
    if (!in || std::memcmp(magic, kMagic, 8) != 0 || version != VertexLightBaker::kVersion || h != hash ||
        count != targets.size())
        return false;
    Fnv sum;
    out.assign(targets.size(), {});
    for (size_t i = 0; i < targets.size(); ++i) {
        uint64_t n = 0;
        in.read(reinterpret_cast<char*>(&n), sizeof n);
        if (!in || n != targets[i].mesh->positions().size()) return false;
        out[i].resize(size_t(n));
        in.read(reinterpret_cast<char*>(out[i].data()), std::streamsize(n * sizeof(vec4)));
        if (!in) return false;
        sum.bytes(out[i].data(), size_t(n) * sizeof(vec4));
    }
    uint64_t stored = 0;
    in.read(reinterpret_cast<char*>(&stored), sizeof stored);
    if (!in || stored != sum.h) return false;
    for (const auto& colors : out)  // a flipped bit that kept the checksum is still refused when not finite
        for (const vec4& c : colors)
            if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b) || !std::isfinite(c.a)) return false;
    return true;
}

void writeCache(const std::string& path, uint64_t hash, const std::vector<std::vector<vec4>>& colors) {
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    // Written beside and renamed: a start that stops half way never leaves a truncated file under the name.
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return;
        const uint32_t version = VertexLightBaker::kVersion;
        const uint64_t count = colors.size();
        out.write(kMagic, 8);
        out.write(reinterpret_cast<const char*>(&version), sizeof version);
        out.write(reinterpret_cast<const char*>(&hash), sizeof hash);
        out.write(reinterpret_cast<const char*>(&count), sizeof count);
        Fnv sum;
        for (const auto& c : colors) {
            const uint64_t n = c.size();
            out.write(reinterpret_cast<const char*>(&n), sizeof n);
            out.write(reinterpret_cast<const char*>(c.data()), std::streamsize(n * sizeof(vec4)));
            sum.bytes(c.data(), c.size() * sizeof(vec4));
        }
        out.write(reinterpret_cast<const char*>(&sum.h), sizeof sum.h);
        if (!out) {
            out.close();
            std::filesystem::remove(tmp, ec);
            return;
        }
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) std::filesystem::remove(tmp, ec);
}

// Throws std::invalid_argument naming VertexLightBaker::compute for a null mesh, a zero or non-finite sun direction,
// negative counts or distances.
void checkComputeArgs(const std::vector<BakeTarget>& targets, const VertexLightParams& p) {
    const char* fn = "VertexLightBaker::compute(): ";
    for (const BakeTarget& t : targets)
        if (!t.mesh) throw std::invalid_argument(std::string(fn) + "null mesh in the targets");
    const double sunLen = glm::length(p.sunDirection);
    if (!std::isfinite(sunLen) || sunLen == 0.0)
        throw std::invalid_argument(std::string(fn) + "sun direction must be finite and non-zero");
    if (p.sunSamples < 0 || p.aoSamples < 0 || !(p.aoDistance >= 0.0) || !(p.sunDistance > 0.0) ||
        !(p.sunAngularRadius >= 0.0) || !(p.offset >= 0.0) || !(p.insetFraction >= 0.0 && p.insetFraction <= 1.0) ||
        !(p.insetMax >= 0.0))
        throw std::invalid_argument(
            std::string(fn) +
            "negative sample count, distance, radius, offset or inset (or an inset fraction above 1)");
}

// Each vertex's triangles (CSR): the inset point is kept on or above them.
struct VertexTriangles {
    std::vector<uint32_t> first, tris;

    VertexTriangles(const Mesh& m, const std::vector<uint32_t>& count)
        : first(m.positions().size() + 1, 0), tris(3 * size_t(m.triangleCount())) {
        for (size_t v = 0; v < count.size(); ++v) first[v + 1] = first[v] + count[v];
        std::vector<uint32_t> fill(first.begin(), first.end() - 1);
        for (uint32_t t = 0; t < m.triangleCount(); ++t)
            for (int k = 0; k < 3; ++k) tris[fill[m.index(3 * t + k)]++] = t;
    }
};

// Lifts `point` by `up` onto the first of vertex v's triangles that the ray up from it meets within `len`.
void liftOntoTriangles(const Mesh& m, const VertexTriangles& vt, size_t v, const dvec3& up, double len, dvec3& point) {
    for (uint32_t k = vt.first[v]; k < vt.first[v + 1]; ++k) {
        const uint32_t t = vt.tris[k];
        MeshBvh::RayHit h;
        const dvec3 a(m.positions()[m.index(3 * t)]), b(m.positions()[m.index(3 * t + 1)]),
            c(m.positions()[m.index(3 * t + 2)]);
        if (MeshBvh::rayTriangle(point, up, len, a, b, c, h) && h.t > 0.0) {
            point += up * h.t;
            break;
        }
    }
}

// Where each vertex samples the light: moved toward the mean centroid of its triangles, since a corner
// of a large face (at the foot of a wall, beside a parapet) would otherwise darken the whole face.
std::vector<dvec3> insetPoints(const Mesh& m, const VertexLightParams& p) {
    std::vector<dvec3> sum(m.positions().size(), dvec3(0.0));
    std::vector<uint32_t> count(m.positions().size(), 0);
    for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t a = m.index(3 * t), b = m.index(3 * t + 1), c = m.index(3 * t + 2);
        const dvec3 centroid = (dvec3(m.positions()[a]) + dvec3(m.positions()[b]) + dvec3(m.positions()[c])) / 3.0;
        for (uint32_t v : {a, b, c}) {
            sum[v] += centroid;
            ++count[v];
        }
    }
    const VertexTriangles vt(m, count);
    std::vector<dvec3> inset(sum.size());
    for (size_t v = 0; v < sum.size(); ++v) {
        const dvec3 pos = dvec3(m.positions()[v]);
        dvec3 d = count[v] ? (sum[v] / double(count[v]) - pos) * p.insetFraction : dvec3(0.0);
        double len = glm::length(d);
        if (!std::isfinite(len))
            d = dvec3(0.0), len = 0.0;
        else if (len > p.insetMax)
            d *= p.insetMax / len, len = p.insetMax;
        inset[v] = pos + d;
        // The mean centroid of a convex bend's triangles (the edge of a bank, a ridge) lies under them, by
        // more than the offset where the bend is sharp: rays from there start under the surface and the
        // vertex comes out black. Lifted along the normal onto its triangle that covers it.
        const dvec3 n = v < m.normals().size() ? dvec3(m.normals()[v]) : dvec3(0.0);
        if (!(len > 0.0) || !(glm::length(n) > 0.0)) continue;
        const dvec3 up = glm::normalize(n);
        liftOntoTriangles(m, vt, v, up, len, inset[v]);
    }
    return inset;
}

// What every vertex's sampling shares: the scene, the parameters, the sun's unit direction L, a frame (lt, lb)
// across it and the tangent of its angular radius.
struct LightSampler {
    const Scene& scene;
    const VertexLightParams& p;
    dvec3 L, lt, lb;
    double coneTan;

    // Of the sun rays from O, jittered over the sun's disc by (r1, r2), those that nothing blocks.
    int freeSunRays(IntersectTraversal& it, Hit& hit, const dvec3& O, double r1, double r2) const {
        int free = 0;
        for (int s = 0; s < p.sunSamples; ++s) {
            const double u1 = std::fmod((s + 0.5) / p.sunSamples + r1, 1.0);
            const double u2 = std::fmod(s * 0.618033988749895 + r2, 1.0);
            const double rad = coneTan * std::sqrt(u1), phi = 2.0 * M_PI * u2;
            const dvec3 d = glm::normalize(L + rad * (std::cos(phi) * lt + std::sin(phi) * lb));
            if (!it.intersect(scene, Ray{O, d, p.sunDistance}, p.query, hit)) ++free;
        }
        return free;
    }

    // Of the cosine-weighted rays from O over N's hemisphere, jittered by (r3, r4), those that meet nothing within
    // aoDistance.
    int freeSkyRays(IntersectTraversal& it, Hit& hit, const dvec3& O, const dvec3& N, double r3, double r4) const {
        dvec3 t, b;
        frame(N, t, b);
        int free = 0;
        for (int s = 0; s < p.aoSamples; ++s) {
            const double u1 = std::fmod((s + 0.5) / p.aoSamples + r3, 1.0);
            const double u2 = std::fmod(s * 0.618033988749895 + r4, 1.0);
            const double rad = std::sqrt(u1), phi = 2.0 * M_PI * u2;
            const dvec3 d = rad * std::cos(phi) * t + rad * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - u1)) * N;
            if (!it.intersect(scene, Ray{O, d, p.aoDistance}, p.query, hit)) ++free;
        }
        return free;
    }

    // The sun and sky of vertex v of target ti (placed by `target`, its normals by `normalMat`), sampled from its
    // inset point, into `out`.
    void bake(IntersectTraversal& it, Hit& hit, const BakeTarget& target, const glm::dmat3& normalMat,
              const dvec3& inset, size_t ti, size_t v, VertexLight& out) const {
        const Mesh& m = *target.mesh;
        const dvec3 P = dvec3(target.world * dvec4(inset, 1.0));
        dvec3 N = v < m.normals().size() ? normalMat * dvec3(m.normals()[v]) : dvec3(0.0);
        const double nl = glm::length(N);
        N = nl > 0.0 && std::isfinite(nl) ? N / nl : dvec3(0, 0, 1);
        const dvec3 O = P + N * p.offset;
        const uint64_t seed = mix64(uint64_t(ti) * 0x100000001b3ull ^ mix64(v));
        // Stratified samples, rotated per vertex (Cranley-Patterson): even coverage, no shared pattern.
        const double r1 = unit(mix64(seed ^ 1)), r2 = unit(mix64(seed ^ 2));
        const double r3 = unit(mix64(seed ^ 3)), r4 = unit(mix64(seed ^ 4));
        const double cosL = glm::dot(N, L);
        if (cosL > 0.0 && p.sunSamples > 0) out.sun[v] = float(freeSunRays(it, hit, O, r1, r2)) / float(p.sunSamples);
        if (p.aoSamples > 0 && p.aoDistance > 0.0)
            out.ao[v] = float(freeSkyRays(it, hit, O, N, r3, r4)) / float(p.aoSamples);
    }
};

}  // namespace

std::vector<VertexLight> VertexLightBaker::compute(const Scene& scene, const std::vector<BakeTarget>& targets,
                                                   const VertexLightParams& p) {
    checkComputeArgs(targets, p);
    const dvec3 L = p.sunDirection / glm::length(p.sunDirection);
    dvec3 lt, lb;
    frame(L, lt, lb);
    const LightSampler sampler{scene, p, L, lt, lb, std::tan(p.sunAngularRadius)};

    std::vector<VertexLight> result(targets.size());
    std::vector<size_t> start(targets.size() + 1, 0);
    std::vector<glm::dmat3> normalMats(targets.size());
    for (size_t i = 0; i < targets.size(); ++i) {
        const size_t n = targets[i].mesh->positions().size();
        result[i].sun.assign(n, 0.0f);
        result[i].ao.assign(n, 1.0f);
        start[i + 1] = start[i] + n;
        normalMats[i] = glm::transpose(glm::inverse(glm::dmat3(targets[i].world)));
    }
    std::vector<std::vector<dvec3>> inset(targets.size());
    for (size_t i = 0; i < targets.size(); ++i) inset[i] = insetPoints(*targets[i].mesh, p);
    const size_t total = start.back();

    // Work is handed out in chunks so that both threads finish together whatever the meshes' sizes.
    constexpr size_t kChunk = 256;
    std::atomic<size_t> next{0};
    auto worker = [&]() {
        IntersectTraversal it;
        Hit hit;
        size_t ti = 0;
        for (;;) {
            const size_t begin = next.fetch_add(kChunk);
            if (begin >= total) break;
            const size_t end = std::min(total, begin + kChunk);
            for (size_t g = begin; g < end; ++g) {
                while (g >= start[ti + 1]) ++ti;
                while (g < start[ti]) --ti;
                const size_t v = g - start[ti];
                sampler.bake(it, hit, targets[ti], normalMats[ti], inset[ti][v], ti, v, result[ti]);
            }
        }
    };
    const int threads = std::max(1, p.threads);
    std::vector<std::thread> pool;
    for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    return result;
}

std::vector<vec4> VertexLightBaker::shade(const Mesh& mesh, const VertexLight& light) {
    const size_t n = mesh.positions().size();
    if (light.sun.size() != n || light.ao.size() != n)
        throw std::invalid_argument("VertexLightBaker::shade(): light has " + std::to_string(light.sun.size()) +
                                    " and " + std::to_string(light.ao.size()) + " values for " + std::to_string(n) +
                                    " vertices");
    std::vector<vec4> out(n);
    const bool hasAlbedo = mesh.colors().size() == n;
    for (size_t i = 0; i < n; ++i) {
        const vec4 albedo = hasAlbedo ? mesh.colors()[i] : vec4(1.0f);
        out[i] = vec4(vec3(albedo) * light.ao[i], light.sun[i]);
    }
    return out;
}

void VertexLightBaker::setColors(Mesh& mesh, std::vector<vec4> colors) {
    std::vector<uint32_t> idx(mesh.indexCount());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = mesh.index(i);
    mesh.set(mesh.positions(), mesh.normals(), std::move(idx), mesh.uvs(), std::move(colors));
}

std::string VertexLightBaker::cachePath(const std::vector<BakeTarget>& targets, const VertexLightParams& params,
                                        uint64_t key, const std::string& dir) {
    for (const BakeTarget& t : targets)
        if (!t.mesh) throw std::invalid_argument("VertexLightBaker::cachePath(): null mesh in the targets");
    char name[96];
    std::snprintf(name, sizeof name, "vertexlight-%016llx-v%u-%016llx.bin", static_cast<unsigned long long>(key),
                  unsigned(kVersion), static_cast<unsigned long long>(inputHash(targets, params, key)));
    return (std::filesystem::path(dir) / name).string();
}

std::string VertexLightBaker::defaultCacheDir() {
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return (std::filesystem::path(x) / "sgkit").string();
    if (const char* h = std::getenv("HOME"); h && *h) return (std::filesystem::path(h) / ".cache" / "sgkit").string();
    return {};
}

bool VertexLightBaker::bakeCached(const Scene& scene, const std::vector<BakeTarget>& targets,
                                  const VertexLightParams& params, uint64_t key, const std::string& dir) {
    for (const BakeTarget& t : targets)
        if (!t.mesh) throw std::invalid_argument("VertexLightBaker::bakeCached(): null mesh in the targets");
    const uint64_t hash = inputHash(targets, params, key);
    const std::string path = dir.empty() ? std::string() : cachePath(targets, params, key, dir);
    std::vector<std::vector<vec4>> colors;
    bool cached = !path.empty() && readCache(path, hash, targets, colors);
    if (!cached) {
        const std::vector<VertexLight> light = compute(scene, targets, params);
        colors.resize(targets.size());
        for (size_t i = 0; i < targets.size(); ++i) colors[i] = shade(*targets[i].mesh, light[i]);
        if (!path.empty()) writeCache(path, hash, colors);
    }
    for (size_t i = 0; i < targets.size(); ++i) setColors(*targets[i].mesh, std::move(colors[i]));
    return cached;
}

}  // namespace sg
