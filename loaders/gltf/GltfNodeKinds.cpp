// sgkit's own node kinds, read from a glTF node's `extras.sgkit` (as saveGltf writes them): Group, LOD, Switch,
// Billboard, BspGroup, PagedLOD, Instance, Occluder and Geometry, each with its settings checked.
#include "loaders/gltf/internal/GltfConverter.h"

#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Instance.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

namespace sg::gltf {

ref_ptr<Node> Converter::pagedLod(const Value& sx, const std::string& xp) {
    auto p = make<PagedLOD>();
    std::string f = string(sx, "file", xp, "");
    if (f.empty()) bad(xp + ".file", "a PagedLOD needs the name of its detail's file");
    const size_t slash = file.find_last_of('/');
    if (f[0] != '/' && slash != std::string::npos) f = file.substr(0, slash + 1) + f;
    p->setFile(f);
    const std::string mode = string(sx, "mode", xp, "distance");
    if (mode != "distance" && mode != "pixelSize") bad(xp + ".mode", "unknown PagedLOD mode '" + mode + "'");
    p->setMode(mode == "distance" ? LOD::Mode::Distance : LOD::Mode::PixelSize);
    const std::string trigger = string(sx, "trigger", xp, "range");
    if (trigger != "range" && trigger != "command") bad(xp + ".trigger", "unknown PagedLOD trigger '" + trigger + "'");
    p->setTrigger(trigger == "range" ? PagedLOD::Trigger::Range : PagedLOD::Trigger::Command);
    try {
        p->setRange(toFloat(number(sx, "min", xp, 0.0), xp + ".min"),
                    sx.Has("max") ? toFloat(number(sx, "max", xp, 0.0), xp + ".max") : kInf);
        if (sx.Has("center")) p->setCenter(vec(sx, "center", xp));
        p->setRadius(number(sx, "radius", xp, 0.0));
    } catch (const std::invalid_argument& e) {
        bad(xp, e.what());
    }
    return p;
}

ref_ptr<Node> Converter::makeKind(const std::string& kind, const Value* sx, const std::string& xp,
                                  const tinygltf::Node& gn, const dmat4& local, const std::string& path) {
    if (kind == "Transform") {
        auto t = make<Transform>();
        if (isTranslation(local))
            t->setTranslation(dvec3(local[3]));
        else
            t->setMatrix(local);
        return t;
    }
    if (kind == "Group") return make<Group>();
    if (kind == "LOD") {
        auto lod = make<LOD>();
        const std::string mode = string(*sx, "mode", xp, "distance");
        if (mode != "distance" && mode != "pixelSize") bad(xp + ".mode", "unknown LOD mode '" + mode + "'");
        lod->setMode(mode == "distance" ? LOD::Mode::Distance : LOD::Mode::PixelSize);
        if (sx->Has("center")) lod->setCenter(vec(*sx, "center", xp));
        if (sx->Has("transition")) {
            try {
                lod->setTransition(toFloat(number(*sx, "transition", xp, 0.0), xp + ".transition"));
            } catch (const std::invalid_argument& e) {
                bad(xp + ".transition", e.what());
            }
        }
        return lod;
    }
    if (kind == "Switch") return make<Switch>();
    if (kind == "Billboard") {
        auto bb = make<Billboard>();
        const std::string mode = string(*sx, "mode", xp, "axial");
        if (mode != "axial" && mode != "pointEye") bad(xp + ".mode", "unknown Billboard mode '" + mode + "'");
        bb->setMode(mode == "axial" ? Billboard::Mode::Axial : Billboard::Mode::PointEye);
        if (sx->Has("axis")) bb->setAxis(vec(*sx, "axis", xp));
        return bb;
    }
    if (kind == "BspGroup") return make<BspGroup>();
    if (kind == "PagedLOD") return pagedLod(*sx, xp);
    if (kind == "Instance") {
        auto in = make<Instance>();
        in->setMatrix(local);
        return in;
    }
    if (kind == "Occluder") {
        auto oc = make<Occluder>();
        if (sx->Has("polygon")) {
            const Value& pv = sx->Get("polygon");
            if (!pv.IsArray()) bad(xp + ".polygon", "must be an array of points");
            std::vector<dvec3> pts;
            for (size_t i = 0; i < pv.ArrayLen(); ++i) {
                const std::vector<double> c = numbers(pv.Get(int(i)), at(xp + ".polygon", i), 3);
                pts.push_back(dvec3(c[0], c[1], c[2]));
            }
            oc->setPolygon(std::move(pts));
        } else {
            Box b;
            b.min = vec(*sx, "min", xp);
            b.max = vec(*sx, "max", xp);
            oc->setBox(b);
        }
        return oc;
    }
    if (kind == "Geometry") {
        if (gn.mesh < 0) {
            auto g = make<Geometry>();
            if (sx->Has("emptyMesh")) g->setMesh(make<Mesh>());
            return g;
        }
        const auto& gs = geometries(gn.mesh);
        if (gs.size() != 1 || !gs[0]) bad(path + ".mesh", "an sgkit Geometry needs a mesh of one triangle primitive");
        auto g = make<Geometry>(ref_ptr<Mesh>(gs[0]->mesh()), ref_ptr<Material>(gs[0]->material()));
        // Its weights and skin are its own (saveGltf writes a skinned or morphed Geometry in its place).
        const int i = int(&gn - m.nodes.data());
        if (targetCount(gn.mesh) > 0) {
            g->setMorphWeights(startWeights(i));
            nodeGeometries[i].push_back(g);
        }
        const int material = m.meshes[size_t(gn.mesh)].primitives[0].material;
        if (material >= 0) materialUsers[material].push_back(g);
        if (gn.skin >= 0 && g->mesh()->influences() > 0) skinned.push_back({i, nullptr, {{size_t(0), g}}});
        return g;
    }
    bad(xp + ".kind", "unknown node kind '" + kind + "'");
}

void Converter::addLevel(LOD& lod, ref_ptr<Node> c, const Value& sx, const std::string& xp, size_t k, size_t nc) {
    const std::vector<double> r = numbers(sx.Get("ranges").Get(int(k)), at(xp + ".ranges", k), 2);
    lod.addChild(std::move(c), toFloat(r[0], at(xp + ".ranges", k)), toFloat(r[1], at(xp + ".ranges", k)));
    if (!sx.Has("errors")) return;
    const Value& errors = sx.Get("errors");
    if (!errors.IsArray() || errors.ArrayLen() != nc)
        bad(xp + ".errors", "needs one error per child (" + std::to_string(nc) + ")");
    const std::vector<double> e = numbers(errors, xp + ".errors", nc);
    lod.setError(lod.numChildren() - 1, toFloat(e[k], at(xp + ".errors", k)));  // given, 0 included
}

}  // namespace sg::gltf
