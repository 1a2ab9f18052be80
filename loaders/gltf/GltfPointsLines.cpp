// glTF points and lines to Meshes (strips and loops made segments, indexed points made their vertices in index
// order), the _INTENSITY attribute of scans, CESIUM_primitive_outline's edges over triangles, and the unlit copy of a
// material that points and lines without normals are drawn with.
#include "loaders/gltf/internal/GltfConverter.h"

#include <cmath>
#include <cstring>

namespace sg::gltf {
namespace {

constexpr const char* kOutline = "CESIUM_primitive_outline";

// v's elements at idx, in order (empty stays empty); idx has been checked against v's size.
template <class T>
std::vector<T> gather(const std::vector<T>& v, const std::vector<uint32_t>& idx) {
    if (v.empty()) return {};
    std::vector<T> out;
    out.reserve(idx.size());
    for (uint32_t i : idx) out.push_back(v[i]);
    return out;
}

std::string vertices(size_t n) { return std::to_string(n) + (n == 1 ? " vertex" : " vertices"); }

}  // namespace

std::vector<uint32_t> Converter::toLines(int mode, const std::vector<uint32_t>& idx, const std::string& path) {
    const size_t n = idx.size();
    std::vector<uint32_t> out;
    if (mode == TINYGLTF_MODE_LINE) {
        out.assign(idx.begin(), idx.begin() + std::ptrdiff_t(n & ~size_t(1)));
        if (n % 2 != 0)
            warn(path, "count " + std::to_string(n) + " is odd (lines): the last index, no whole segment, left out");
        return out;
    }
    const char* kind = mode == TINYGLTF_MODE_LINE_LOOP ? "line loop" : "line strip";
    if (n < 2) {
        warn(path, std::string("a ") + kind + " of " + vertices(n) + " has no segment");
        return out;
    }
    out.reserve(2 * n);
    for (size_t i = 1; i < n; ++i) out.insert(out.end(), {idx[i - 1], idx[i]});
    if (mode == TINYGLTF_MODE_LINE_LOOP) out.insert(out.end(), {idx[n - 1], idx[0]});  // closed back to the first
    return out;
}

void Converter::pointsOrLines(const tinygltf::Primitive& p, const std::string& path, std::vector<vec3> positions,
                              const std::vector<uint32_t>& idx, Mesh& mesh) {
    auto attr = [&](const char* name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    const int col = attr("COLOR_0"), nrm = attr("NORMAL");
    std::vector<vec4> colors = col >= 0 ? readVectors<vec4, 4>(m, col) : std::vector<vec4>{};
    if (p.mode != TINYGLTF_MODE_POINTS) {  // lines have no normals to light them by
        const std::string where = path + (p.indices >= 0 ? ".indices" : ".attributes.POSITION");
        mesh.setLines(std::move(positions), toLines(p.mode, idx, where), std::move(colors));
        return;
    }
    std::vector<vec3> normals = nrm >= 0 ? readUnitVectors<vec3>(m, nrm) : std::vector<vec3>{};
    if (p.indices >= 0) {  // points have no indices: the vertices they name become the points
        positions = gather(positions, idx);
        colors = gather(colors, idx);
        normals = gather(normals, idx);
    }
    mesh.setPoints(std::move(positions), std::move(colors), std::move(normals));
}

ref_ptr<MeshFeatures> Converter::gathered(const MeshFeatures& f, const std::vector<uint32_t>& idx) {
    auto out = make<MeshFeatures>(f);
    for (FeatureIdSet& s : out->sets) {
        if (s.source == FeatureIdSet::Source::Attribute) {
            s.ids = gather(s.ids, idx);
        } else if (s.source == FeatureIdSet::Source::Implicit) {  // the id was the vertex's index in the file
            s.source = FeatureIdSet::Source::Attribute;
            s.ids = idx;
        }
    }
    for (PropertyAttributeValues& a : out->propertyAttributes)
        for (PropertyAttributeValues::Column& c : a.columns) {
            const size_t stride = c.stride;
            std::vector<uint8_t> bytes(idx.size() * stride);
            for (size_t k = 0; k < idx.size(); ++k)
                if ((size_t(idx[k]) + 1) * stride <= c.bytes.size())  // else Mesh::setFeatures() names the column
                    std::memcpy(bytes.data() + k * stride, c.bytes.data() + idx[k] * stride, stride);
            c.bytes = std::move(bytes);
        }
    return out;
}

// _INTENSITY: a scanner's return strength, one scalar per vertex of any glTF component type. Integers that are not
// normalized and floats are the value itself (LAS's 0..65535); normalized integers are a fraction of 65535.
std::vector<uint16_t> Converter::intensities(const tinygltf::Primitive& p, size_t n, const std::string& path,
                                             const std::vector<uint32_t>* order) {
    auto it = p.attributes.find("_INTENSITY");
    if (it == p.attributes.end()) return {};
    const std::string ap = path + ".attributes._INTENSITY";
    const tinygltf::Accessor& a = m.accessors[size_t(it->second)];  // validate() has checked it and its count
    const int c = a.componentType;
    if (a.type != TINYGLTF_TYPE_SCALAR || c == TINYGLTF_COMPONENT_TYPE_INT || c == TINYGLTF_COMPONENT_TYPE_DOUBLE)
        bad(ap, "accessor " + std::to_string(it->second) + " is not a SCALAR of one of glTF's component types");
    const AccessorReader r(m, a);
    std::vector<uint16_t> out(n);
    for (size_t i = 0; i < n && i < a.count; ++i) {
        // component() reads 4 bytes as a float: an unsigned int is read as the integer it is.
        double v = c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT ? double(r.index(i)) : double(r.component(i, 0));
        if (!std::isfinite(v)) bad(ap, "element " + std::to_string(i) + " is not finite");
        if (a.normalized) v *= 65535.0;
        out[i] = uint16_t(std::lround(std::clamp(v, 0.0, 65535.0)));
    }
    return order ? gather(out, *order) : out;
}

std::string Converter::outlineKey(const tinygltf::Primitive& p) {
    auto it = p.extensions.find(kOutline);
    if (it == p.extensions.end()) return {};
    const Value& x = it->second;
    const bool named = x.IsObject() && x.Has("indices") && x.Get("indices").IsNumber();
    return std::string("outline=") + (named ? std::to_string(x.Get("indices").GetNumberAsDouble()) : "?") + ";";
}

void Converter::outline(const tinygltf::Primitive& p, Mesh& mesh, const std::string& path) {
    auto it = p.extensions.find(kOutline);
    if (it == p.extensions.end()) return;
    const std::string xp = path + ".extensions." + kOutline, ip = xp + ".indices";
    if (mesh.primitive() != Primitive::Triangles) {
        warn(xp, "only triangles have an outline, ignored");
        return;
    }
    const Value& x = it->second;
    if (!x.IsObject() || !x.Has("indices")) bad(ip, "missing: the outline names no accessor");
    const Value& v = x.Get("indices");
    const double d = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
    if (!(d >= 0.0 && d < double(m.accessors.size()) && d == std::floor(d)))
        bad(ip, "must name one of the " + std::to_string(m.accessors.size()) + " accessors");
    const size_t acc = size_t(d);
    const tinygltf::Accessor& a = m.accessors[acc];
    const int c = a.componentType;
    if (a.type != TINYGLTF_TYPE_SCALAR ||
        (c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        bad(ip, "accessor " + std::to_string(acc) + " is not a SCALAR of an unsigned integer type");
    if (a.count % 2 != 0)
        bad(ip, "accessor " + std::to_string(acc) + " has an odd count " + std::to_string(a.count) +
                    ": an outline is pairs of vertices");
    const size_t n = mesh.positions().size();
    const AccessorReader r(m, a);
    std::vector<uint32_t> edges(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        edges[i] = r.index(i);
        if (edges[i] >= n)
            bad(ip, "index " + std::to_string(edges[i]) + " at element " + std::to_string(i) + " is out of range (" +
                        vertices(n) + ")");
    }
    mesh.setOutline(std::move(edges));
}

ref_ptr<Material> Converter::unlit(const ref_ptr<Material>& mat) {
    if (!mat || mat->unlit) return mat;  // none: the renderer's default for points and lines
    ref_ptr<Material>& u = unlitMaterials[mat.get()];
    if (!u) {
        u = make<Material>(*mat);
        u->unlit = true;
    }
    return u;
}

}  // namespace sg::gltf
