// glTF test helpers: a scene with every node kind, a graph comparison, and small glTF documents written
// from a JSON fragment plus vertex data (as .gltf text with an embedded buffer, or as .glb).
#pragma once
#include "loaders/gltf/Gltf.h"
#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace gltftest {

using namespace sg;

// Every node kind and parameter the glTF extras carry, with shared meshes, materials and subgraphs.
inline ref_ptr<Group> allKindsScene() {
    auto box = makeBoxMesh(dvec3(-1), dvec3(1), 2);
    auto slab = makeBoxMesh(dvec3(-2, -0.1, 0), dvec3(2, 0.1, 3));
    auto red = make<Material>(vec4(0.9f, 0.2f, 0.1f, 1.0f));
    auto green = make<Material>(vec4(0.1f, 0.8f, 0.3f, 0.5f));
    green->unlit = true;
    green->alphaCutoff = 0.3f;
    auto root = make<Group>();
    root->setName("scene");

    auto shared = make<Geometry>(box, red);  // one Geometry under two parents
    auto t1 = make<Transform>(glm::translate(dmat4(1.0), dvec3(3, 0, 0)));
    t1->setName("translated");
    t1->addChild(shared);
    auto t2 = make<Transform>(glm::scale(glm::rotate(dmat4(1.0), 0.7, dvec3(0, 0, 1)), dvec3(1, 2, 0.5)));
    t2->setName("general");
    t2->addChild(shared);
    t2->addChild(make<Geometry>(box, green));  // same mesh, another material
    root->addChild(t1);
    root->addChild(t2);

    auto lod = make<LOD>();
    lod->setName("lod");
    lod->setCenter(dvec3(0.5, 0.25, -1));
    lod->addChild(make<Geometry>(box, red), 0.0f, 12.5f);
    lod->addChild(make<Geometry>(slab, red), 12.5f, 1e5f);
    lod->setError(1, 0.375f);
    root->addChild(lod);
    auto plod = make<LOD>();
    plod->setMode(LOD::Mode::PixelSize);
    plod->addChild(make<Geometry>(slab, green), 40.0f, 1e9f);
    plod->setError(0, 0.0f);    // given, as 0: the budget reads it as exact
    plod->setTransition(6.5f);  // a fade band of 6.5 px
    root->addChild(plod);

    auto sw = make<Switch>();
    sw->setName("switch");
    sw->addChild(make<Geometry>(box, red), true);
    sw->addChild(make<Geometry>(slab, red), false);
    sw->addChild(make<Group>(), true);
    root->addChild(sw);

    auto bb = make<Billboard>();
    bb->setMode(Billboard::Mode::PointEye);
    bb->setAxis(dvec3(0, 1, 1));
    bb->addChild(make<Geometry>(slab, green));
    auto bb2 = make<Billboard>();
    bb2->addChild(make<Geometry>(slab, red));
    root->addChild(bb);
    root->addChild(bb2);

    auto proto = make<Group>();
    proto->setName("prototype");
    proto->addChild(make<Geometry>(slab, red));
    root->addChild(make<Instance>(proto, glm::translate(dmat4(1.0), dvec3(10, 0, 0))));
    root->addChild(
        make<Instance>(proto, glm::rotate(glm::translate(dmat4(1.0), dvec3(-10, 0, 0)), 1.0, dvec3(0, 1, 0))));

    auto bsp = make<BspGroup>();
    for (int i = 0; i < 4; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(i * 3.0, -6, 0)));
        t->addChild(shared);
        bsp->addChild(t);
    }
    root->addChild(bsp);

    auto wall = make<Occluder>();
    wall->setBox(Box{dvec3(-5, -1, -5), dvec3(5, 1, 5)});
    auto quad = make<Occluder>();
    quad->setPolygon({dvec3(0, 0, 0), dvec3(4, 0, 0), dvec3(4, 0, 3), dvec3(0, 0, 3)});
    root->addChild(wall);
    root->addChild(quad);

    auto masked = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 20, 0)));
    masked->setNodeMask(0x5u);
    masked->addChild(make<Geometry>(box, red));
    auto pickOnly = make<Geometry>(slab, green);
    pickOnly->setNodeMask(0xfffffff0u);
    masked->addChild(pickOnly);
    root->addChild(masked);
    root->addChild(make<Geometry>());                                   // no mesh
    root->addChild(make<Geometry>(make<Mesh>(), ref_ptr<Material>()));  // an empty mesh (written as a flag)
    return root;
}

inline Node* findByName(Node& n, const std::string& name) {
    if (n.name() == name) return &n;
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (Node* f = findByName(*n.child(i), name)) return f;
    return nullptr;
}

// Structure, kinds, names, masks, per-kind parameters, mesh and material contents, and sharing (a node
// shared in `a` is shared the same way in `b`). On a difference: false, with `why` naming the node.
inline bool sameGraph(const Node& a, const Node& b, std::map<const Node*, const Node*>& seen, std::string& why) {
    auto differ = [&](const std::string& what) {
        why = a.describe() + ": " + what;
        return false;
    };
    auto it = seen.find(&a);
    if (it != seen.end()) return it->second == &b ? true : differ("sharing differs");
    seen[&a] = &b;
    if (a.kind() != b.kind()) return differ(std::string("kind ") + b.kindName());
    if (a.name() != b.name()) return differ("name '" + b.name() + "'");
    if (a.nodeMask() != b.nodeMask()) return differ("node mask");
    if (a.numParents() != b.numParents()) return differ("parent count");
    if (a.numChildren() != b.numChildren()) return differ("child count");
    switch (a.kind()) {
        case NodeKind::Transform:
            if (static_cast<const Transform&>(a).matrix() != static_cast<const Transform&>(b).matrix())
                return differ("matrix");
            break;
        case NodeKind::Instance:
            if (static_cast<const Instance&>(a).matrix() != static_cast<const Instance&>(b).matrix())
                return differ("matrix");
            break;
        case NodeKind::LOD: {
            const auto &la = static_cast<const LOD&>(a), &lb = static_cast<const LOD&>(b);
            if (la.mode() != lb.mode() || la.userCenter() != lb.userCenter() || la.center() != lb.center())
                return differ("mode or centre");
            if (la.transition() != lb.transition() || la.hasErrors() != lb.hasErrors())
                return differ("transition or whether errors are given");
            for (size_t i = 0; i < la.numChildren(); ++i)
                if (la.range(i).min != lb.range(i).min || la.range(i).max != lb.range(i).max ||
                    la.error(i) != lb.error(i))
                    return differ("range or error " + std::to_string(i));
            break;
        }
        case NodeKind::Switch:
            for (size_t i = 0; i < a.numChildren(); ++i)
                if (static_cast<const Switch&>(a).isOn(i) != static_cast<const Switch&>(b).isOn(i))
                    return differ("switch state " + std::to_string(i));
            break;
        case NodeKind::Billboard: {
            const auto &ba = static_cast<const Billboard&>(a), &bb = static_cast<const Billboard&>(b);
            // setAxis() normalizes: an axis read back is normalized once more (a last-bit difference at most).
            if (ba.mode() != bb.mode() || glm::length(ba.axis() - bb.axis()) > 4e-16) return differ("mode or axis");
            break;
        }
        case NodeKind::Occluder: {
            const auto &oa = static_cast<const Occluder&>(a), &ob = static_cast<const Occluder&>(b);
            if (oa.shape() != ob.shape() || oa.box().min != ob.box().min || oa.box().max != ob.box().max ||
                oa.polygon() != ob.polygon())
                return differ("shape");
            break;
        }
        case NodeKind::Geometry: {
            const auto &ga = static_cast<const Geometry&>(a), &gb = static_cast<const Geometry&>(b);
            const Mesh *ma = ga.mesh(), *mb = gb.mesh();
            if (!ma != !mb) return differ("mesh presence");
            if (ma && (ma->positions() != mb->positions() || ma->normals() != mb->normals() || ma->uvs() != mb->uvs() ||
                       ma->colors() != mb->colors() || ma->indices16() != mb->indices16() ||
                       ma->indices32() != mb->indices32()))
                return differ("mesh data");
            const Material *ta = ga.material(), *tb = gb.material();
            if (!ta != !tb) return differ("material presence");
            if (ta && (ta->baseColor != tb->baseColor || ta->unlit != tb->unlit || ta->alphaCutoff != tb->alphaCutoff ||
                       !ta->texture != !tb->texture || (ta->texture && ta->texture->rgba() != tb->texture->rgba())))
                return differ("material");
            break;
        }
        default: break;
    }
    for (size_t i = 0; i < a.numChildren(); ++i)
        if (!sameGraph(*a.child(i), *b.child(i), seen, why)) return false;
    return true;
}

inline void expectSameGraph(const Node& a, const Node& b) {
    std::map<const Node*, const Node*> seen;
    std::string why;
    EXPECT_TRUE(sameGraph(a, b, seen, why)) << why;
    // Distinct nodes stay distinct.
    std::map<const Node*, const Node*> back;
    for (const auto& [x, y] : seen) back[y] = x;
    EXPECT_EQ(back.size(), seen.size());
}

inline uint32_t le32(const std::string& s, size_t at) {
    uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = v << 8 | uint8_t(s[at + size_t(k)]);
    return v;
}
inline void setLe32(std::string& s, size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) s[at + size_t(k)] = char(v >> (8 * k));
}

inline std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
        const uint32_t v = uint32_t(uint8_t(in[i])) << 16;
        out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}

// A small glTF document: `json` holds the scene, nodes and meshes; the buffer, views and accessors are
// added: accessor 0 = positions (VEC3 float, view 0), accessor 1 = indices (uint16, view 1).
struct Doc {
    std::string json;
    std::vector<vec3> positions{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<uint16_t> indices{0, 1, 2};
    size_t positionCount = 0;  // 0: positions.size()
    size_t positionStride = 0;
    size_t viewExtra = 0;        // added to view 0's byteLength
    std::string extraAccessors;  // appended to the accessor list
    std::string externalBin;     // buffer by this URI instead of embedded
    std::string extraBytes;      // after the indices, as bufferViews[2] (accessors address it by byteOffset)

    std::string binary() const {
        std::string b(reinterpret_cast<const char*>(positions.data()), positions.size() * sizeof(vec3));
        b.append(reinterpret_cast<const char*>(indices.data()), indices.size() * 2);
        b.resize((b.size() + 3) & ~size_t(3), '\0');
        b += extraBytes;
        b.resize((b.size() + 3) & ~size_t(3), '\0');
        return b;
    }
    std::string parts(bool glb) const {
        const std::string bin = binary();
        const size_t pbytes = positions.size() * sizeof(vec3);
        std::ostringstream o;
        o << R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": )" << bin.size();
        if (!glb)
            o << R"(, "uri": ")"
              << (externalBin.empty() ? "data:application/octet-stream;base64," + base64(bin) : externalBin) << '"';
        o << R"(}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": )" << pbytes + viewExtra;
        if (positionStride) o << R"(, "byteStride": )" << positionStride;
        o << R"(}, {"buffer": 0, "byteOffset": )" << pbytes << R"(, "byteLength": )" << indices.size() * 2 << "}";
        if (!extraBytes.empty())
            o << R"(, {"buffer": 0, "byteOffset": )" << ((pbytes + indices.size() * 2 + 3) & ~size_t(3))
              << R"(, "byteLength": )" << extraBytes.size() << "}";
        o << "]";
        o << R"(, "accessors": [{"bufferView": 0, "componentType": 5126, "count": )"
          << (positionCount ? positionCount : positions.size()) << R"(, "type": "VEC3"}, )";
        o << R"({"bufferView": 1, "componentType": 5123, "count": )" << indices.size() << R"(, "type": "SCALAR"})"
          << extraAccessors << "]";
        o << ", " << json << "}";
        return o.str();
    }
    std::string text() const { return parts(false); }
    std::string glb() const {
        std::string j = parts(true);
        j.resize((j.size() + 3) & ~size_t(3), ' ');
        const std::string bin = binary();
        std::string out(20, '\0');
        out.replace(0, 4, "glTF");
        setLe32(out, 4, 2);
        setLe32(out, 12, uint32_t(j.size()));
        setLe32(out, 16, 0x4E4F534Au);
        out += j;
        std::string head(8, '\0');
        setLe32(head, 0, uint32_t(bin.size()));
        setLe32(head, 4, 0x004E4942u);
        out += head + bin;
        setLe32(out, 8, uint32_t(out.size()));
        return out;
    }
    GltfScene load() const {
        const std::string t = text();
        return loadGltfFromMemory("doc.gltf", t.data(), t.size());
    }
};

}  // namespace gltftest
