// EXT_mesh_gpu_instancing: a node's per-instance translation, rotation and scale read into matrices, its
// instances built as Instances of one prototype (with the node's EXT_instance_features), and instance matrices split
// back into float translation, rotation and scale for writing.
#include "loaders/gltf/internal/GltfConverter.h"

#include "nodes/Instance.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>

namespace sg::gltf {

using tinygltf::Value;

const Value* instancing(const tinygltf::Node& n) {
    auto it = n.extensions.find(kInstancing);
    return it == n.extensions.end() ? nullptr : &it->second;
}

size_t instanceCount(const tinygltf::Model& m, const tinygltf::Node& n) {
    const Value& attrs = instancing(n)->Get("attributes");
    return m.accessors[size_t(attrs.Get(attrs.Keys().front()).GetNumberAsInt())].count;
}

dmat4 composeTrs(const dvec3& t, const dvec4& q, const dvec3& s) {
    const glm::dquat r(q.w, q.x, q.y, q.z);
    dmat4 m = glm::mat4_cast(r / glm::length(r));
    m[0] *= s.x;
    m[1] *= s.y;
    m[2] *= s.z;
    m[3] = dvec4(t, 1.0);
    return m;
}

std::vector<dmat4> instanceMatrices(const std::string& file, const tinygltf::Model& m, int node, const dmat4& world) {
    const tinygltf::Node& gn = m.nodes[size_t(node)];
    const Value& attrs = instancing(gn)->Get("attributes");
    const std::string path = at("nodes", size_t(node)) + ".extensions." + kInstancing + ".attributes";
    const char* names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    const int comps[3] = {3, 4, 3};
    std::vector<AccessorReader> readers;  // per attribute present
    std::vector<int> present;
    for (int k = 0; k < 3; ++k) {
        if (!attrs.Has(names[k])) continue;
        readers.emplace_back(m, m.accessors[size_t(attrs.Get(names[k]).GetNumberAsInt())]);
        present.push_back(k);
    }
    const size_t n = instanceCount(m, gn);
    std::vector<dmat4> out(n);
    double v[3][4] = {{0, 0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1, 0}};  // identity where an attribute is absent
    for (size_t i = 0; i < n; ++i) {
        for (size_t a = 0; a < present.size(); ++a) {
            const int k = present[a];
            bool finite = true;
            for (int c = 0; c < comps[k]; ++c) finite &= std::isfinite(v[k][c] = double(readers[a].component(i, c)));
            if (finite) continue;
            std::string text;
            for (int c = 0; c < comps[k]; ++c) text += (c ? ", " : "") + std::to_string(v[k][c]);
            fail(file, path + "." + names[k], "instance " + std::to_string(i) + " (" + text + ") is not finite");
        }
        const dvec4 q(v[1][0], v[1][1], v[1][2], v[1][3]);
        if (!(glm::length(q) > 0.0))
            fail(file, path + ".ROTATION", "instance " + std::to_string(i) + " is a quaternion of zero length");
        out[i] = composeTrs(dvec3(v[0][0], v[0][1], v[0][2]), q, dvec3(v[2][0], v[2][1], v[2][2]));
        const std::string overflow = nonFiniteElement(world * out[i]);
        if (!overflow.empty())
            fail(file, path, "instance " + std::to_string(i) + "'s world matrix is not finite (" + overflow + ")");
    }
    return out;
}

void Converter::levelOfInstancedLod(LOD& lod, const tinygltf::Node& gn, const Value& sx, const std::string& xp,
                                    const std::string& path) {
    const Value* ranges = sx.Has("ranges") ? &sx.Get("ranges") : nullptr;
    if (!ranges || !ranges->IsArray() || ranges->ArrayLen() != 1)
        bad(xp + ".ranges", "an instanced LOD needs one [min, max] range, its mesh's");
    const auto& gs = geometries(gn.mesh);
    if (gs.size() != 1 || !gs[0]) bad(path + ".mesh", "an instanced sgkit LOD needs a mesh of one triangle primitive");
    try {
        addLevel(lod, gs[0], sx, xp, 0, 1);
    } catch (const std::invalid_argument& e) {
        bad(xp + ".ranges", e.what());
    }
}

void Converter::instances(int i, Group* into, const dmat4& world, const std::string& path, ref_ptr<LOD> lodPrototype) {
    const tinygltf::Node& gn = m.nodes[size_t(i)];
    const std::string xp = path + ".extensions." + kInstancing + ".attributes";
    instancesDone += instanceCount(m, gn);
    if (instancesDone > kMaxInstances)
        bad(xp, "the file places more than " + std::to_string(kMaxInstances) + " instances");
    const std::vector<dmat4> placements = instanceMatrices(file, m, i, world);
    std::vector<ref_ptr<Geometry>> drawn;
    for (const auto& g : geometries(gn.mesh))
        if (g) drawn.push_back(g);
    if (drawn.empty()) return;  // every primitive skipped, with a warning each
    ref_ptr<Node> proto = drawn[0];
    if (lodPrototype) {
        proto = lodPrototype;
    } else if (drawn.size() > 1) {
        auto& group = prototypes[gn.mesh];
        if (!group) {
            group = make<Group>();
            for (const auto& g : drawn) group->addChild(g);
        }
        proto = group;
    }
    const std::string scale = instancing(gn)->Get("attributes").Has("SCALE") ? xp + ".SCALE" : xp;
    const ref_ptr<const MeshFeatures> features = instanceFeatures(i, placements.size(), path);
    std::vector<ref_ptr<Node>> placed;
    std::vector<dvec3> where;
    for (size_t k = 0; k < placements.size(); ++k) {
        try {
            auto in = make<Instance>(proto, placements[k]);
            if (features) in->setFeatures(features, uint32_t(k));
            placed.push_back(in);
            where.push_back(dvec3(placements[k][3]));
        } catch (const std::invalid_argument& e) {  // a singular matrix: rotations are not, so the scale
            bad(scale, "instance " + std::to_string(k) + " cannot be placed (" + e.what() + ")");
        }
    }
    addNearbyGrouped(*into, placed, where);
}

bool splitTrs(const dmat4& m, FloatTrs& out) {
    if (!nonAffineRow(m).empty() || !nonFiniteElement(m).empty()) return false;
    const dvec3 c[3] = {dvec3(m[0]), dvec3(m[1]), dvec3(m[2])};
    dvec3 s(glm::length(c[0]), glm::length(c[1]), glm::length(c[2]));
    const double largest = std::max(s.x, std::max(s.y, s.z));
    if (!(s.x > 0.0 && s.y > 0.0 && s.z > 0.0)) return false;
    if (glm::dot(c[0], glm::cross(c[1], c[2])) < 0.0) s.x = -s.x;  // a mirror: one negative scale
    const glm::dquat r = glm::normalize(glm::quat_cast(glm::dmat3(c[0] / s.x, c[1] / s.y, c[2] / s.z)));
    out.t = vec3(dvec3(m[3]));
    out.q = vec4(float(r.x), float(r.y), float(r.z), float(r.w));
    out.s = vec3(s);
    if (!isFinite(dvec3(out.t)) || !isFinite(dvec3(out.s)) || out.s.x == 0.0f || out.s.y == 0.0f || out.s.z == 0.0f)
        return false;  // beyond float's range either way
    // Recomposed from the floats as the reader will: a shear (which no T * R * S holds) shows up here.
    const dmat4 back = composeTrs(dvec3(0.0), dvec4(out.q), dvec3(out.s));
    for (int col = 0; col < 3; ++col)
        for (int k = 0; k < 3; ++k)
            if (!(std::abs(back[col][k] - m[col][k]) <= 1e-6 * largest)) return false;
    return true;
}

namespace {

constexpr size_t kGroupSize = 32;  // placements per group at most: a few frustum tests against one saved

void split(Group& into, const std::vector<ref_ptr<Node>>& nodes, const std::vector<dvec3>& at, uint32_t* first,
           uint32_t* last) {
    const size_t n = size_t(last - first);
    if (n <= kGroupSize) {
        for (uint32_t* k = first; k != last; ++k) into.addChild(nodes[*k]);
        return;
    }
    Box b;
    for (uint32_t* k = first; k != last; ++k) b.expand(at[*k]);
    const dvec3 size = b.max - b.min;
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : size.y >= size.z ? 1 : 2;
    uint32_t* mid = first + n / 2;
    std::nth_element(first, mid, last, [&](uint32_t a, uint32_t c) { return at[a][axis] < at[c][axis]; });
    for (auto [b0, e0] : {std::make_pair(first, mid), std::make_pair(mid, last)}) {
        auto g = make<Group>();
        split(*g, nodes, at, b0, e0);
        into.addChild(g);
    }
}

}  // namespace

void addNearbyGrouped(Group& into, const std::vector<ref_ptr<Node>>& nodes, const std::vector<dvec3>& at) {
    std::vector<uint32_t> order(nodes.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
    split(into, nodes, at, order.data(), order.data() + order.size());
}

}  // namespace sg::gltf
