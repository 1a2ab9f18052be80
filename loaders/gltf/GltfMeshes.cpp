// glTF mesh primitives to shared Meshes and Geometries: one Mesh per distinct primitive (strips and fans made
// triangles, points and lines as GltfPointsLines.cpp reads them; its source, intensities, outline, features, skin
// weights and morph targets set), tangents made for normal maps, classic materials' UV transforms applied to a copy.
#include "loaders/gltf/internal/GltfConverter.h"

#include <cmath>

namespace sg::gltf {

void Converter::toTriangles(int mode, std::vector<uint32_t>& idx) {
    std::vector<uint32_t> t;
    for (size_t i = 2; i < idx.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            const bool odd = (i % 2) == 1;  // keep the winding of the first triangle
            t.insert(t.end(), {idx[i - 2 + (odd ? 1 : 0)], idx[i - 1 - (odd ? 1 : 0)], idx[i]});
        } else {
            t.insert(t.end(), {idx[0], idx[i - 1], idx[i]});
        }
    }
    idx = std::move(t);
}

ref_ptr<Mesh> Converter::mesh(const tinygltf::Primitive& p, const std::string& path, int gm, int prim) {
    auto attr = [&](const char* name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    const int pos = attr("POSITION"), nrm = attr("NORMAL"), uv = attr("TEXCOORD_0"), col = attr("COLOR_0"),
              tan = attr("TANGENT"), uv1 = attr("TEXCOORD_1");
    const auto key = std::make_tuple(p.mode, p.indices, pos, nrm, uv, col, tan, uv1,
                                     featureKey(p) + outlineKey(p) + motionKey(p, gm));
    auto found = meshes.find(key);
    if (found != meshes.end()) return found->second;

    std::vector<vec3> positions = readVectors<vec3, 3>(m, pos);
    const size_t n = positions.size();
    std::vector<uint32_t> idx = indices(p, n, path);
    // Indexed points are their indexed vertices, in index order: what is per vertex is taken at the indices.
    const bool gather = p.mode == TINYGLTF_MODE_POINTS && p.indices >= 0;
    std::vector<uint16_t> strengths = intensities(p, n, path, gather ? &idx : nullptr);
    auto mesh = make<Mesh>();
    try {
        if (p.mode < TINYGLTF_MODE_TRIANGLES) {
            pointsOrLines(p, path, std::move(positions), idx, *mesh);
        } else {
            if (p.mode != TINYGLTF_MODE_TRIANGLES) toTriangles(p.mode, idx);
            if (idx.size() % 3 != 0) {  // glTF draws the whole triangles (the validator warns)
                warn(path, std::to_string(idx.size()) + (p.indices >= 0 ? " indices" : " vertices") +
                               " are not a multiple of 3 (TRIANGLES): the last " + std::to_string(idx.size() % 3) +
                               " left out");
                idx.resize(idx.size() - idx.size() % 3);
            }
            mesh->set(std::move(positions), nrm >= 0 ? readUnitVectors<vec3>(m, nrm) : std::vector<vec3>{},
                      std::move(idx), uv >= 0 ? readVectors<vec2, 2>(m, uv) : std::vector<vec2>{},
                      col >= 0 ? readVectors<vec4, 4>(m, col) : std::vector<vec4>{});
            mesh->setSurface(tan >= 0 ? readUnitVectors<vec4>(m, tan) : std::vector<vec4>{},
                             uv1 >= 0 ? readVectors<vec2, 2>(m, uv1) : std::vector<vec2>{});
        }
        mesh->setIntensities(std::move(strengths));
    } catch (const std::exception& e) {
        bad(path, e.what());
    }
    outline(p, *mesh, path);
    skinWeights(p, *mesh, path, gather ? &idx : nullptr);
    morphTargets(p, *mesh, path, gm, gather ? &idx : nullptr);
    if (!mesh->validBound()) {
        const auto& ps = mesh->positions();
        size_t i = 0;
        while (std::isfinite(ps[i].x) && std::isfinite(ps[i].y) && std::isfinite(ps[i].z)) ++i;
        bad(path + ".attributes.POSITION", "element " + std::to_string(i) + " is not finite (" +
                                               std::to_string(ps[i].x) + ", " + std::to_string(ps[i].y) + ", " +
                                               std::to_string(ps[i].z) + ")");
    }
    mesh->setSource({file, gm, prim});
    if (ref_ptr<MeshFeatures> f = primitiveFeatures(p, n, path)) {
        if (gather) f = gathered(*f, idx);
        try {
            mesh->setFeatures(std::move(f));
        } catch (const std::invalid_argument& e) {  // what primitiveFeatures checked: a count it missed
            bad(path + ".extensions", e.what());
        }
    }
    meshes[key] = mesh;
    return mesh;
}

void Converter::withTangents(Mesh& mesh, const Material* mat) {
    if (!mat || !mat->physical || !mat->pbr.normal.texture || !mesh.tangents().empty()) return;
    const int set = mat->pbr.normal.texCoord;
    const size_t n = mesh.positions().size();
    if (mesh.normals().size() != n || (set == 0 ? mesh.uvs() : mesh.uvs1()).size() != n) return;
    mesh.setSurface(generateTangents(mesh, set), mesh.uvs1());
}

ref_ptr<Mesh> Converter::withUvTransform(const ref_ptr<Mesh>& mesh, int mat, int set) {
    ref_ptr<Mesh>& out = classicUvMeshes[{mesh.get(), mat}];
    if (out) return out;
    const mat3& t = classicUv[mat];
    std::vector<vec2> uvs = mesh->uvs(), uvs1 = mesh->uvs1();
    for (vec2& uv : set == 0 ? uvs : uvs1) uv = vec2(t * vec3(uv, 1.0f));
    std::vector<uint32_t> idx(mesh->indexCount());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = mesh->index(i);
    out = make<Mesh>();
    out->set(mesh->positions(), mesh->normals(), std::move(idx), std::move(uvs), mesh->colors());
    out->setSurface(mesh->tangents(), std::move(uvs1));
    out->setIntensities(mesh->intensities());
    out->setOutline(mesh->outline());
    out->setFeatures(ref_ptr<const MeshFeatures>(mesh->features()));
    out->setSource(mesh->source());
    if (mesh->influences() > 0) out->setSkinWeights(mesh->joints(), mesh->weights(), mesh->influences());
    out->setMorphTargets(mesh->morphTargets());
    out->defaultWeights = mesh->defaultWeights;
    return out;
}

const std::vector<ref_ptr<Geometry>>& Converter::geometries(int i) {
    if (sharedDone[size_t(i)]) return shared[size_t(i)];
    sharedDone[size_t(i)] = true;
    auto& gs = shared[size_t(i)];
    const auto& prims = m.meshes[size_t(i)].primitives;
    targetCount(i);  // refuses primitives of different target counts before any is read
    for (size_t k = 0; k < prims.size(); ++k) {
        const tinygltf::Primitive& p = prims[k];
        const std::string path = at(at("meshes", size_t(i)) + ".primitives", k);
        if (!p.attributes.count("POSITION")) {
            warn(path, "no POSITION attribute, primitive skipped");
            gs.push_back({});
        } else if (const std::string why = missingData(p); !why.empty()) {
            warn(path, why);
            gs.push_back({});
        } else {
            ref_ptr<Mesh> mh = mesh(p, path, i, int(k));
            ref_ptr<Material> mat = material(p.material);
            if (mh->primitive() != Primitive::Triangles) {
                if (mh->normals().empty()) mat = unlit(mat);  // glTF: points and lines without normals are unlit
            } else {
                if (classicUv.count(p.material)) mh = withUvTransform(mh, p.material, mat->texCoord);
                withTangents(*mh, mat.get());
            }
            auto g = make<Geometry>(std::move(mh), std::move(mat));
            // Its mesh's default weights; a plain node's own copies take the node's (ownGeometries()).
            if (!g->mesh()->morphTargets().empty()) g->setMorphWeights(g->mesh()->defaultWeights);
            if (p.material >= 0) materialUsers[p.material].push_back(g);
            gs.push_back(std::move(g));
        }
    }
    progress.report(0.6 + 0.4 * double(nodesDone) / double(std::max<size_t>(1, m.nodes.size())), "converting");
    return gs;
}

}  // namespace sg::gltf
