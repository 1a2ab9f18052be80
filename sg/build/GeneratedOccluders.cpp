// Occluders over a graph (GeneratedOccluders.h, generateOccluders): each Geometry's and LOD's shapes
// (MeshOccluders.cpp) as Occluder nodes beside them, with the conditions the pass checks (why each shape is inside what
// it stands for is in MeshOccluders.cpp).
#include "sg/build/GeneratedOccluders.h"

#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "sg/core/Material.h"
#include "sg/scene/internal/OccluderShapes.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace sg {

namespace {

bool opaque(const Geometry& g) {
    const Material* m = g.material();
    return !m || (!m->blend && !(m->alphaCutoff > 0.0f));
}

struct Generator {
    const OccluderGenSettings& s;
    OccluderGenStats& st;
    std::unordered_map<const Mesh*, MeshOccluders> cache;

    const MeshOccluders& shapes(const Mesh& m) {
        auto it = cache.find(&m);
        if (it != cache.end()) return it->second;
        st.meshes++;
        st.meshTriangles += m.triangleCount();
        return cache.emplace(&m, meshOccluders(m, s)).first->second;
    }

    static ref_ptr<Occluder> box(const Box& b, const Box& eyeOutside, const std::vector<Plane>& openings) {
        auto o = make<Occluder>();
        o->setBox(b);
        o->setEyeOutside(eyeOutside);
        o->setOpenings(openings);
        o->setGenerated(true);
        return o;
    }

    // Occluders for a Geometry child: its mesh's boxes (eye outside its bound, and beyond its openings' planes) or
    // polygons.
    void geometry(const Geometry& g, std::vector<ref_ptr<Occluder>>& add) {
        const Mesh* m = g.mesh();
        if (!m) return;
        st.sceneTriangles += m->triangleCount();
        if (!opaque(g)) {
            st.skipped++;
            return;
        }
        const MeshOccluders& sh = shapes(*m);
        for (const Box& b : sh.boxes) add.push_back(box(b, m->box(), {}));
        for (const Box& b : sh.cappedBoxes) add.push_back(box(b, m->box(), sh.openings));
        for (const auto& p : sh.polygons) {
            auto o = make<Occluder>();
            try {
                o->setPolygon(p);
            } catch (const std::invalid_argument&) {
                continue;  // a sliver the polygon check refuses: left out
            }
            o->setGenerated(true);
            o->setOneSided(g.material() && !g.material()->doubleSided);
            add.push_back(o);
        }
    }

    // An LOD's levels' shapes, whether any level is one-sided, and the levels' bound.
    struct Levels {
        std::vector<const MeshOccluders*> shapes;
        bool oneSided = false;
        Box bound;
    };

    // The shapes of an LOD's levels; false when a level is not an opaque Geometry with a mesh, shown always.
    bool levelsOf(LOD& l, Levels& lv) {
        const size_t levels = l.numChildren();
        for (size_t c = 0; c < levels; ++c) {
            const Node* ch = l.child(c);
            if (ch->kind() != NodeKind::Geometry || ch->nodeMask() != 0xffffffffu) return false;
            const auto& g = static_cast<const Geometry&>(*ch);
            if (!g.mesh()) return false;
            st.sceneTriangles += g.mesh()->triangleCount();
            if (!opaque(g)) {
                st.skipped++;
                return false;
            }
            lv.oneSided = lv.oneSided || (g.material() && !g.material()->doubleSided);
            lv.shapes.push_back(&shapes(*g.mesh()));
            lv.bound.expand(g.mesh()->box());
        }
        return true;
    }

    static const std::vector<Box>* boxesOf(const MeshOccluders* m) { return m->closed ? &m->boxes : &m->cappedBoxes; }

    // Boxes when every level has some (inside its solid, or inside it with its openings capped: then used beyond
    // every level's openings' planes, gathered in `openings`).
    static std::vector<Box> commonBoxes(const std::vector<const MeshOccluders*>& shapesOf,
                                        std::vector<Plane>& openings) {
        const bool solid =
            std::all_of(shapesOf.begin(), shapesOf.end(), [&](const MeshOccluders* m) { return !boxesOf(m)->empty(); });
        std::vector<Box> common;
        if (!solid) return common;
        common = *boxesOf(shapesOf[0]);
        for (const MeshOccluders* m : shapesOf) openings.insert(openings.end(), m->openings.begin(), m->openings.end());
        for (size_t c = 1; c < shapesOf.size(); ++c) {
            std::vector<Box> next;
            for (const Box& a : common)
                for (const Box& b : *boxesOf(shapesOf[c])) {
                    const Box x{glm::max(a.min, b.min), glm::min(a.max, b.max)};
                    if (x.min.x < x.max.x && x.min.y < x.max.y && x.min.z < x.max.z) next.push_back(x);
                }
            common = std::move(next);
        }
        return common;
    }

    // The parts of the first level's polygons that every level's polygons cover too, those keeping enough of their
    // area.
    std::vector<std::vector<dvec3>> commonPolygons(const std::vector<const MeshOccluders*>& shapesOf,
                                                   const Box& bound) {
        std::vector<std::vector<dvec3>> polys;
        const double tol = occluders::flatTolerance(bound);
        for (const auto& p0 : shapesOf[0]->polygons) {
            std::vector<dvec3> p = p0;
            const dvec3 n = occluders::polygonNormal(p0);
            for (size_t c = 1; c < shapesOf.size() && !p.empty(); ++c) {
                std::vector<dvec3> best;
                for (const auto& q : shapesOf[c]->polygons) {
                    std::vector<dvec3> x = occluders::clipConvex(p, q, n, tol);
                    if (!x.empty() && (best.empty() || occluders::polygonArea(x) > occluders::polygonArea(best)))
                        best = std::move(x);
                }
                p = std::move(best);
            }
            if (!p.empty() && occluders::polygonArea(p) >= s.minPolygonShare * occluders::polygonArea(p0))
                polys.push_back(std::move(p));
        }
        return polys;
    }

    // The largest of an LOD's common boxes, shown with it.
    void addLevelBoxes(LOD& l, std::vector<Box>& common, const Box& bound, const std::vector<Plane>& openings,
                       std::vector<ref_ptr<Occluder>>& add) {
        using occluders::volume;
        std::stable_sort(common.begin(), common.end(),
                         [](const Box& p, const Box& q) { return volume(p) > volume(q); });
        const double minVol = s.minBoxShare * volume(bound);
        for (size_t k = 0; k < common.size() && k < s.maxBoxes && volume(common[k]) >= minVol; ++k) {
            auto o = box(common[k], bound, openings);
            o->setShownWith(&l);
            add.push_back(o);
        }
    }

    // An LOD's common polygons, shown with it.
    static void addLevelPolygons(LOD& l, std::vector<std::vector<dvec3>>& polys, bool oneSided,
                                 std::vector<ref_ptr<Occluder>>& add) {
        for (auto& p : polys) {
            auto o = make<Occluder>();
            try {
                o->setPolygon(std::move(p));
            } catch (const std::invalid_argument&) {
                continue;  // a sliver the polygon check refuses: left out
            }
            o->setGenerated(true);
            o->setOneSided(oneSided);
            o->setShownWith(&l);
            add.push_back(o);
        }
    }

    // Occluders inside every level of an LOD whose levels are all opaque Geometry: boxes inside every level (when all
    // have boxes, closed or capped), or else the parts of the first level's polygons that every open level's polygons
    // cover too.
    void lod(LOD& l, std::vector<ref_ptr<Occluder>>& add) {
        Levels lv;
        if (!levelsOf(l, lv) || lv.shapes.empty()) return;
        const bool open =
            std::none_of(lv.shapes.begin(), lv.shapes.end(), [](const MeshOccluders* m) { return m->closed; });
        std::vector<Plane> openings;
        std::vector<Box> common = commonBoxes(lv.shapes, openings);
        std::vector<std::vector<dvec3>> polys;
        if (common.empty() && open) polys = commonPolygons(lv.shapes, lv.bound);
        addLevelBoxes(l, common, lv.bound, openings, add);
        addLevelPolygons(l, polys, lv.oneSided, add);
    }

    // The Geometry nodes in a subtree left without occluders (an LOD's levels counted as one).
    static uint64_t geometriesIn(const Node& n) {
        if (n.kind() == NodeKind::Geometry || n.kind() == NodeKind::LOD) return 1;
        if (n.kind() == NodeKind::Instance) return 0;
        uint64_t k = 0;
        for (size_t c = 0; c < n.numChildren(); ++c) k += geometriesIn(*n.child(c));
        return k;
    }

    static bool hidesWholeSubtree(const Node& n) {
        const NodeKind k = n.kind();
        return k == NodeKind::Billboard || k == NodeKind::Instance;
    }

    void visit(Node& n) {
        if (hidesWholeSubtree(n)) {
            st.skipped += geometriesIn(n);
            return;
        }
        if (n.kind() == NodeKind::LOD) return;  // its levels are handled beside it, by its parent
        const bool canHold = n.kind() == NodeKind::Group || n.kind() == NodeKind::Transform;
        bool authored = false;
        for (size_t c = 0; c < n.numChildren(); ++c) authored = authored || n.child(c)->kind() == NodeKind::Occluder;
        // (position, occluder): inserted after the walk of the children, from the back.
        std::vector<std::pair<size_t, ref_ptr<Occluder>>> inserts;
        for (size_t c = 0; c < n.numChildren(); ++c) {
            Node* ch = n.child(c);
            const bool leaf = ch->kind() == NodeKind::Geometry || ch->kind() == NodeKind::LOD;
            if (leaf && ch->nodeMask() != 0xffffffffu) {
                st.skipped++;
                continue;
            }
            if (leaf && (!canHold || authored)) {
                st.skipped++;
                continue;
            }
            std::vector<ref_ptr<Occluder>> add;
            if (ch->kind() == NodeKind::Geometry)
                geometry(static_cast<Geometry&>(*ch), add);
            else if (ch->kind() == NodeKind::LOD)
                lod(static_cast<LOD&>(*ch), add);
            else
                visit(*ch);
            for (auto& o : add) inserts.push_back({c + 1, std::move(o)});
        }
        dropEnclosed(inserts);
        for (auto& in : inserts)
            pending.push_back({static_cast<Group*>(&n), in.first, std::move(in.second), n.child(in.first - 1)});
    }

    // A polygon within the bound of a mesh beside it that got boxes (a roof over a building's walls, a floor inside
    // them) is left out: seen from outside that bound the boxes stand for the whole, and the polygon would add only
    // the rim between a box and the bound, at the cost of a candidate the pass must weigh every frame.
    void dropEnclosed(std::vector<std::pair<size_t, ref_ptr<Occluder>>>& inserts) {
        std::vector<Box> bounds;
        for (const auto& in : inserts)
            if (in.second->shape() == Occluder::Shape::Box && !in.second->eyeOutside().empty())
                bounds.push_back(in.second->eyeOutside());
        if (bounds.empty()) return;
        auto enclosed = [&](const Occluder& o) {
            if (o.shape() != Occluder::Shape::Polygon) return false;
            for (const Box& b : bounds) {
                const double tol = occluders::flatTolerance(b);
                const bool in = std::all_of(o.polygon().begin(), o.polygon().end(), [&](const dvec3& v) {
                    return glm::all(glm::greaterThanEqual(v, b.min - tol)) &&
                           glm::all(glm::lessThanEqual(v, b.max + tol));
                });
                if (in) return true;
            }
            return false;
        };
        const size_t before = inserts.size();
        inserts.erase(
            std::remove_if(inserts.begin(), inserts.end(), [&](const auto& in) { return enclosed(*in.second); }),
            inserts.end());
        st.enclosed += before - inserts.size();
    }

    struct Pending {
        Group* group;
        size_t at;
        ref_ptr<Occluder> occ;
        const Node* source;  // the Geometry or LOD it stands for
    };
    std::vector<Pending> pending;  // in walk order: within a group, by position

    // Largest face area: a box's two largest extents, a polygon's area.
    static double face(const Occluder& o) {
        if (o.shape() == Occluder::Shape::Polygon) return occluders::polygonArea(o.polygon());
        const dvec3 e = o.box().max - o.box().min;
        return std::max({e.x * e.y, e.y * e.z, e.x * e.z});
    }

    // Keeps the major occluders (a face at least minMajorShare of the largest one's) and inserts them, each group's
    // from the back so that positions hold.
    void insert() {
        double largest = 0.0;
        for (const Pending& p : pending) largest = std::max(largest, face(*p.occ));
        std::unordered_set<const Node*> sources;
        for (size_t k = pending.size(); k-- > 0;) {
            const Pending& p = pending[k];
            if (face(*p.occ) < s.minMajorShare * largest) {
                st.minor++;
                continue;
            }
            p.group->insertChild(p.at, p.occ);
            if (sources.insert(p.source).second) st.geometries++;
            if (p.occ->shape() == Occluder::Shape::Box)
                st.boxes++;
            else
                st.polygons++;
            if (p.occ->shownWith()) st.lods++;
        }
    }
};

}  // namespace

OccluderGenStats generateOccluders(Node& root, const OccluderGenSettings& s) {
    s.validate("sg::generateOccluders()");
    const auto t0 = std::chrono::steady_clock::now();
    removeOccluders(root, true);
    OccluderGenStats st;
    Generator g{s, st, {}, {}};
    g.visit(root);
    g.insert();
    st.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return st;
}

size_t removeOccluders(Node& root, bool generatedOnly) {
    size_t removed = 0;
    if (root.kind() == NodeKind::Instance) return 0;  // a prototype is not below it in the graph's sense
    for (size_t c = root.numChildren(); c-- > 0;) {
        Node* ch = root.child(c);
        if (ch->kind() == NodeKind::Occluder) {
            if (generatedOnly && !static_cast<Occluder*>(ch)->generated()) continue;
            static_cast<Group&>(root).removeChild(c);
            removed++;
        } else {
            removed += removeOccluders(*ch, generatedOnly);
        }
    }
    return removed;
}

}  // namespace sg
