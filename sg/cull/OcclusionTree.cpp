#include "sg/cull/OcclusionTree.h"

#include "sg/core/Camera.h"

#include <algorithm>
#include <cmath>

namespace sg {

namespace {
constexpr double kRel = eps::kRounding;  // rounding allowance, relative to the magnitudes in play
// Growing the tree, a polygon within this (relative) distance of a plane is not split by it: the sliver
// would add nodes and hide nothing. Either side is safe, as every chain is the shadow of a real part.
constexpr double kInsertRel = 1e-6;

inline double mag1(const dvec3& v) { return std::abs(v.x) + std::abs(v.y) + std::abs(v.z); }

// The 26 outlines, worked out once from the faces that face the eye: a box edge is on the outline when
// exactly one of its two faces faces the eye.
struct Outlines {
    uint8_t corner[27][6];
    uint8_t count[27];
    Outlines() {
        for (int r = 0; r < 27; ++r) {
            const int reg[3] = {r % 3, (r / 3) % 3, r / 9};
            count[r] = 0;
            if (reg[0] == 1 && reg[1] == 1 && reg[2] == 1) continue;
            auto front = [&](int axis, int bit) {
                return (bit == 0 && reg[axis] == 0) || (bit == 1 && reg[axis] == 2);
            };
            int next[8][2];
            int deg[8] = {0};
            for (int c = 0; c < 8; ++c)
                for (int b = 0; b < 3; ++b) {
                    if (c & (1 << b)) continue;
                    const int a1 = (b + 1) % 3, a2 = (b + 2) % 3;
                    if (front(a1, (c >> a1) & 1) == front(a2, (c >> a2) & 1)) continue;
                    const int d = c | (1 << b);
                    next[c][deg[c]++] = d;
                    next[d][deg[d]++] = c;
                }
            int start = 0;
            while (deg[start] == 0) ++start;
            int prev = -1, cur = start;
            do {
                corner[r][count[r]++] = uint8_t(cur);
                const int nx = next[cur][0] == prev ? next[cur][1] : next[cur][0];
                prev = cur;
                cur = nx;
            } while (cur != start && count[r] < 6);
        }
    }
};
const Outlines& outlines() {
    static const Outlines o;
    return o;
}

inline dvec3 cornerOf(const dvec3& lo, const dvec3& hi, int k) {
    return dvec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
}
}  // namespace

int OcclusionTree::silhouette(int rx, int ry, int rz, uint8_t out[6]) {
    const int r = rx + 3 * ry + 9 * rz;
    const Outlines& o = outlines();
    for (int k = 0; k < o.count[r]; ++k) out[k] = o.corner[r][k];
    return o.count[r];
}

OcclusionTree::Options OcclusionTree::optionsFor(const Camera& cam, const OcclusionSettings& s) {
    s.validate("OcclusionTree::optionsFor()");
    Options o;
    o.cap = s.measureOnly.cap;
    o.hasNear = true;
    o.nearPlane = cam.eyePlanes()[4];
    const double zNear = std::max(-o.nearPlane.d, 0.0);
    o.nearPlane.d -= 1e-5 * zNear;  // what lies within rounding of the near plane may be clipped: not used
    // A 64th of a pixel: the rasterizer snaps vertices to 1/256 pixel, occluder and occludee alike.
    o.edgeMargin = (1.0 / 64.0) / std::max(cam.pixelsPerUnit(), 1e-9);
    // A 24-bit depth buffer separates depths that differ by z^2 / (near 2^24): keep 8 steps clear of it. A float
    // reverse-Z buffer's interpolation errs as much on a triangle reaching the near plane (architecture.md, Depth).
    o.depthMargin = zNear > 0 ? 8.0 / (zNear * 16777216.0) : 0.0;
    o.screenSplits = s.measureOnly.screenSplits;
    o.viewToWorld = glm::transpose(glm::dmat3(cam.viewRotation()));
    const dmat4& p = cam.projection();
    o.tanX = 1.0 / std::max(std::abs(p[0][0]), 1e-12) + std::abs(p[2][0]);
    o.tanY = 1.0 / std::max(std::abs(p[1][1]), 1e-12) + std::abs(p[2][1]);
    return o;
}

void OcclusionTree::reset(const dvec3& eye, const Options& o) {
    opt_ = o;
    eye_ = eye;
    // World coordinates carry rounding of their magnitude (a transform's product, a box 10,000 km out):
    // eye-relative points are only that exact, and the tests allow for it.
    worldErr_ = 16.0 * 2.220446049250313e-16 * std::max({std::abs(eye.x), std::abs(eye.y), std::abs(eye.z)});
    nodes_.clear();
    pool_.clear();
    polySplits_ = boxSplits_ = 0;
    root_ = kVisible;
    if (o.screenSplits > 0) splitScreen(&root_, o.screenSplits, -o.tanX, o.tanX, -o.tanY, o.tanY);
}

// A balanced top level: planes through the eye halving the screen, alternately across and down.
void OcclusionTree::splitScreen(int32_t* slot, int level, double x0, double x1, double y0, double y1) {
    if (level == 0) return;
    const bool vertical = (x1 - x0) >= (y1 - y0);
    const double m = vertical ? 0.5 * (x0 + x1) : 0.5 * (y0 + y1);
    // View space looks down -Z: the point (X, Y, Z) is at screen tangent X / -Z; the plane X + m Z = 0.
    const dvec3 nv = vertical ? dvec3(1, 0, m) : dvec3(0, 1, m);
    const int32_t k = newNode(glm::normalize(opt_.viewToWorld * nv), 0.0, Kind::Split, kVisible, kVisible);
    *slot = k;
    int32_t in = kVisible, out = kVisible;
    if (vertical) {
        splitScreen(&in, level - 1, x0, m, y0, y1);
        splitScreen(&out, level - 1, m, x1, y0, y1);
    } else {
        splitScreen(&in, level - 1, x0, x1, y0, m);
        splitScreen(&out, level - 1, x0, x1, m, y1);
    }
    nodes_[k].in = in;
    nodes_[k].out = out;
}

int32_t OcclusionTree::newNode(const dvec3& n, double d, Kind k, int32_t in, int32_t out) {
    nodes_.push_back(Node{n, d, in, out, k});
    return int32_t(nodes_.size() - 1);
}

void OcclusionTree::setSlot(int32_t parent, bool inSide, int32_t v) {
    if (parent < 0)
        root_ = v;
    else
        (inSide ? nodes_[parent].in : nodes_[parent].out) = v;
}

void OcclusionTree::split(Poly p, const dvec3& n, double d, Poly& in, Poly& out) {
    // Both parts in one pass over the edges: the part with s <= 0, then the one with s >= 0.
    double small[16];
    std::vector<double> big;
    double* s = small;
    if (p.count > 16) {
        big.resize(p.count);
        s = big.data();
    }
    for (uint32_t i = 0; i < p.count; ++i) s[i] = glm::dot(n, pool_[p.first + i].p) + d;
    const uint32_t first = uint32_t(pool_.size());
    pool_.resize(first + 2 * (p.count + 1));  // room for both: each gains at most one vertex
    Vertex* vin = &pool_[first];
    Vertex* vout = vin + p.count + 1;
    uint32_t ni = 0, no = 0;
    for (uint32_t i = 0; i < p.count; ++i) {
        const uint32_t j = i + 1 == p.count ? 0 : i + 1;
        const Vertex a = pool_[p.first + i], b = pool_[p.first + j];
        const double sa = s[i], sb = s[j];
        // The edge leaving a kept vertex toward a dropped one ends on the plane; from there the outline
        // runs along the plane: a cut.
        if (sa <= 0) vin[ni++] = {a.p, a.cut || (sb > 0 && sa == 0)};
        if (sa >= 0) vout[no++] = {a.p, a.cut || (sb < 0 && sa == 0)};
        if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) {
            const dvec3 x = a.p + (b.p - a.p) * (sa / (sa - sb));
            vin[ni++] = {x, sa < 0 ? true : a.cut};
            vout[no++] = {x, sa > 0 ? true : a.cut};
        }
    }
    in = Poly{first, ni};
    out = Poly{first + p.count + 1, no};
}

// Walks the tree from the slot (parent, inSide) down; adds chains where the polygon reaches visible
// leaves. Classifying wrongly here only loses culling: every chain added is the shadow of a real part of
// the occluder, whichever cell it lands in.
bool OcclusionTree::insert(int32_t parent, bool inSide, Poly p, const Occ& o) {
    const int32_t cur = parent < 0 ? root_ : (inSide ? nodes_[parent].in : nodes_[parent].out);
    if (cur == kOccluded) return false;
    if (cur == kVisible) return chain(parent, inSide, p, o);
    const Node nd = nodes_[cur];
    if (nd.kind == Kind::Cap) {
        // Points within a hair of the cap (coplanar faces of a row of buildings) count as behind it:
        // a shadow added in the thin slab in front of it would hide next to nothing.
        bool neg = false, pos = false;
        for (int k = 0; k < o.extentCount; ++k) {
            const double s = glm::dot(nd.n, o.extent[k]) + nd.d, t = kInsertRel * mag1(o.extent[k]);
            neg |= s < t;
            pos |= s >= t;
        }
        bool added = false;
        if (pos) added |= insert(cur, false, p, o);
        if (neg) added |= insert(cur, true, p, o);  // behind this cap, maybe in front of the next one
        return added;
    }
    bool neg = false, pos = false;
    for (uint32_t i = 0; i < p.count; ++i) {
        const dvec3& v = pool_[p.first + i].p;
        const double s = glm::dot(nd.n, v), t = kInsertRel * mag1(v);
        neg |= s < -t;
        pos |= s > t;
    }
    if (!pos) return insert(cur, true, p, o);
    if (!neg) return insert(cur, false, p, o);
    const size_t mark = pool_.size();
    Poly in, out;
    split(p, nd.n, 0.0, in, out);
    polySplits_++;
    bool added = false;
    if (out.count >= 3) added |= insert(cur, false, out, o);
    if (in.count >= 3) added |= insert(cur, true, in, o);
    pool_.resize(mark);
    return added;
}

// The shadow of polygon p, in the cell at (parent, inSide): a plane through the eye and each edge, then
// the occluder's caps, then an occluded leaf.
bool OcclusionTree::chain(int32_t parent, bool inSide, Poly p, const Occ& o) {
    if (o.capCount == 0) return false;
    dvec3 inward(0.0);  // a direction inside the polygon's cone
    for (uint32_t i = 0; i < p.count; ++i) {
        const dvec3 a = pool_[p.first + i].p, b = pool_[p.first + (i + 1) % p.count].p;
        const double la = glm::length(a), lb = glm::length(b);
        if (!(la > 0.0 && lb > 0.0)) return false;
        // An edge that spans nearly half the view: narrowing its plane (below) could widen the cone
        // behind the eye. Such occluders are too close to matter; leave them out.
        if (glm::dot(a, b) < -0.98 * la * lb) return false;
        inward += a / la;
    }
    const size_t first = nodes_.size();
    for (uint32_t i = 0; i < p.count; ++i) {
        // A cut lies on a plane the cell is already on the right side of: no node, and no margin (a
        // margin there would open a crack between the two parts of one occluder).
        if (pool_[p.first + i].cut) continue;
        const dvec3 a = pool_[p.first + i].p, b = pool_[p.first + (i + 1) % p.count].p;
        const dvec3 e = b - a;
        const double la = glm::length(a), lb = glm::length(b);
        dvec3 n = glm::cross(a, e);
        const double len = glm::length(n);
        // An edge seen end-on projects to a point: its neighbours already bound the cone there.
        if (!(len > kRel * glm::length(a) * glm::length(e))) continue;
        n /= len;
        const double side = glm::dot(n, inward);
        if (std::abs(side) <= kRel * glm::length(inward)) {  // seen edge-on: no area
            nodes_.resize(first);
            return false;
        }
        if (side > 0) n = -n;  // inside the cone: negative
        // Narrow the cone by the margin: turn the plane about the line through the eye along the edge.
        const dvec3 ee = e / glm::length(e), mid = 0.5 * (a + b);
        const double sinEdge = glm::length(glm::cross(glm::normalize(mid), ee));
        const double theta = std::min(opt_.edgeMargin / std::max(sinEdge, 0.05), 20.0 * opt_.edgeMargin) +
                             4.0 * worldErr_ / (std::min(la, lb) * std::max(sinEdge, 0.05));
        const dvec3 rot = glm::cross(ee, n);
        const double sgn = glm::dot(rot, mid) >= 0 ? 1.0 : -1.0;
        n = glm::normalize(n * std::cos(theta) + rot * (sgn * std::sin(theta)));
        newNode(n, 0.0, Kind::Edge, int32_t(nodes_.size() + 1), kVisible);
    }
    for (int k = 0; k < o.capCount; ++k)
        newNode(o.caps[k].n, o.caps[k].d, Kind::Cap, int32_t(nodes_.size() + 1), kVisible);
    nodes_.back().in = kOccluded;
    setSlot(parent, inSide, int32_t(first));
    return true;
}

bool OcclusionTree::insertBox(const Box& box, const dmat4* toWorld) {
    if (box.empty() || !isFinite(box.min) || !isFinite(box.max)) return false;
    if (toWorld && (!nonFiniteElement(*toWorld).empty() || !nonAffineRow(*toWorld).empty())) return false;
    dvec3 el = eye_;
    if (toWorld) {
        const glm::dmat3 a(*toWorld);
        if (!(std::abs(glm::determinant(a)) > eps::kDegenerate)) return false;
        el = glm::inverse(a) * (eye_ - dvec3((*toWorld)[3]));
    }
    int reg[3];
    for (int k = 0; k < 3; ++k) reg[k] = el[k] < box.min[k] ? 0 : el[k] > box.max[k] ? 2 : 1;
    if (reg[0] == 1 && reg[1] == 1 && reg[2] == 1) return false;  // the eye is inside (or on) it
    dvec3 c[8];
    double zmax = 0.0;
    bool beyondNear = true;
    for (int k = 0; k < 8; ++k) {
        const dvec3 lc = cornerOf(box.min, box.max, k);
        c[k] = toWorld ? dvec3(*toWorld * dvec4(lc, 1.0)) - eye_ : lc - eye_;
        zmax = std::max(zmax, glm::length(c[k]));
        if (opt_.hasNear && !(opt_.nearPlane.distance(c[k]) > kRel * mag1(c[k]))) beyondNear = false;
    }
    // Cut by the near plane: what is drawn is the front faces' parts beyond it.
    if (!beyondNear) return insertFaces(c, reg);

    Occ o;
    o.extent = c;
    o.extentCount = 8;
    const double margin = opt_.depthMargin * zmax * zmax + 4.0 * worldErr_;
    if (opt_.cap == OccluderCap::FrontFaces) {
        // Behind every face that faces the eye: behind the box along any ray through its outline.
        for (int a = 0; a < 3; ++a) {
            if (reg[a] == 1) continue;
            const int bit = reg[a] == 2 ? 1 : 0;
            // Face corners: the corner with this bit, and its neighbours in the other two axes.
            const int k0 = bit << a, k1 = k0 | (1 << ((a + 1) % 3)), k2 = k0 | (1 << ((a + 2) % 3));
            dvec3 n = glm::cross(c[k1] - c[k0], c[k2] - c[k0]);
            const double len = glm::length(n);
            if (!(len > 0.0)) return false;
            n /= len;
            double d = -glm::dot(n, c[k0]);
            if (d < 0) n = -n, d = -d;  // the eye on the positive side
            o.caps[o.capCount++] = Plane{n, d + margin + kRel * (std::abs(d) + zmax)};
        }
    } else {
        // The paper's plane: through the centre, facing the eye. Rays that graze the box cross it
        // before they reach the box, so this culls what can be seen.
        dvec3 ctr(0.0);
        for (const dvec3& p : c) ctr += p * 0.125;
        const double dist = glm::length(ctr);
        if (!(dist > 0)) return false;
        o.caps[o.capCount++] = Plane{-ctr / dist, dist + margin};
    }
    uint8_t ring[6];
    const int cnt = silhouette(reg[0], reg[1], reg[2], ring);
    const uint32_t first = uint32_t(pool_.size());
    for (int k = 0; k < cnt; ++k) pool_.push_back({c[ring[k]], false});
    const bool added = insert(-1, false, Poly{first, uint32_t(cnt)}, o);
    pool_.resize(first);
    return added;
}

// A box cut by the near plane: each face that faces the eye, clipped to the near plane, as a polygon.
bool OcclusionTree::insertFaces(const dvec3 c[8], const int reg[3]) {
    bool added = false;
    for (int a = 0; a < 3; ++a) {
        if (reg[a] == 1) continue;
        const int bit = reg[a] == 2 ? 1 : 0, b1 = 1 << ((a + 1) % 3), b2 = 1 << ((a + 2) % 3);
        const int k0 = bit << a;
        const dvec3 face[4] = {c[k0], c[k0 | b1], c[k0 | b1 | b2], c[k0 | b2]};
        added |= insertPlanar(face, 4);
    }
    return added;
}

bool OcclusionTree::insertPolygon(const dvec3* v, size_t count) {
    if (!v || count < 3) return false;
    std::vector<dvec3> rel(count);
    for (size_t i = 0; i < count; ++i) {
        if (!isFinite(v[i])) return false;
        rel[i] = v[i] - eye_;
    }
    return insertPlanar(rel.data(), count);
}

// A convex planar polygon, eye-relative: clipped to the near plane, capped by its own plane.
bool OcclusionTree::insertPlanar(const dvec3* v, size_t count) {
    std::vector<dvec3> poly(v, v + count);
    if (opt_.hasNear) {
        std::vector<dvec3> kept;
        const Plane& np = opt_.nearPlane;
        for (size_t i = 0; i < poly.size(); ++i) {
            const dvec3 a = poly[i], b = poly[(i + 1) % poly.size()];
            const double sa = np.distance(a) - kRel * mag1(a), sb = np.distance(b) - kRel * mag1(b);
            if (sa > 0) kept.push_back(a);
            if ((sa > 0) != (sb > 0)) {
                // Stay on the kept side of the crossing: nudge the cut point a little further in.
                const dvec3 x = a + (b - a) * (sa / (sa - sb));
                const dvec3 inside = sa > 0 ? a : b;
                kept.push_back(x + (inside - x) * 1e-9);
            }
        }
        poly.swap(kept);
        if (poly.size() < 3) return false;
    }
    dvec3 n(0.0);
    double zmax = 0.0, size = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        n += glm::cross(poly[i], poly[(i + 1) % poly.size()]);
        zmax = std::max(zmax, glm::length(poly[i]));
        size = std::max(size, glm::length(poly[i] - poly[0]));
    }
    const double len = glm::length(n);
    if (!(len > 0.0)) return false;
    n /= len;
    double d = -glm::dot(n, poly[0]);
    if (d < 0) n = -n, d = -d;
    if (!(d > eps::kCoplanar * size + kRel * zmax)) return false;  // the eye on its plane: seen edge-on
    Occ o;
    o.caps[0] = Plane{n, d + opt_.depthMargin * zmax * zmax + kRel * (d + zmax) + 4.0 * worldErr_};
    o.capCount = 1;
    o.extent = poly.data();
    o.extentCount = int(poly.size());
    const uint32_t first = uint32_t(pool_.size());
    for (const dvec3& v : poly) pool_.push_back({v, false});
    const bool added = insert(-1, false, Poly{first, uint32_t(poly.size())}, o);
    pool_.resize(first);
    return added;
}

// Is every point of the planar polygon p in occluded leaves below `node`? Only "inside" decisions need to
// be certain: every outside child is a whole chain (or a leaf), whose occluded leaves are real shadows
// wherever the walk entered them.
bool OcclusionTree::occluded(int32_t node, Poly p, double mag) {
    while (node >= 0) {
        const Node& nd = nodes_[node];
        const double t = kRel * (mag + std::abs(nd.d)) + worldErr_;
        bool allIn = true, anyIn = false;
        for (uint32_t i = 0; i < p.count; ++i) {
            const double s = glm::dot(nd.n, pool_[p.first + i].p) + nd.d;
            allIn &= s < -t;
            anyIn |= s < -t;
        }
        if (allIn) {
            node = nd.in;
        } else if (!anyIn) {
            node = nd.out;
        } else {
            const size_t mark = pool_.size();
            const int32_t in = nd.in, out = nd.out;
            Poly pin, pout;
            split(p, nd.n, nd.d, pin, pout);
            boxSplits_++;
            const bool r = (pout.count < 3 || occluded(out, pout, mag)) && (pin.count < 3 || occluded(in, pin, mag));
            pool_.resize(mark);
            return r;
        }
    }
    return node == kOccluded;
}

OcclusionTree::Result OcclusionTree::testRelative(const dvec3& lo, const dvec3& hi, int32_t& resume) {
    if (resume == kVisible) return Result::Visible;
    if (!isFinite(lo) || !isFinite(hi) || !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return Result::Partial;
    int reg[3];
    for (int k = 0; k < 3; ++k) reg[k] = hi[k] < 0 ? 2 : lo[k] > 0 ? 0 : 1;
    if (reg[0] == 1 && reg[1] == 1 && reg[2] == 1) return Result::Partial;  // the eye inside: seen
    // Descend while the whole box is on one side: boxes inside it start their tests there. A plane's
    // range over the box is its value at the centre plus or minus the extent's reach along the normal.
    const dvec3 ctr = 0.5 * (lo + hi), ext = 0.5 * (hi - lo);
    const double mag = mag1(glm::max(glm::abs(lo), glm::abs(hi)));  // bounds |p|_1 over the box
    int32_t node = resume;
    while (node >= 0) {
        const Node& nd = nodes_[node];
        const double sc = glm::dot(nd.n, ctr) + nd.d, reach = glm::dot(glm::abs(nd.n), ext);
        const double t = kRel * (mag + std::abs(nd.d)) + 1e-15 * reach + worldErr_;
        if (sc + reach < -t)
            node = nd.in;
        else if (sc - reach >= -t)
            node = nd.out;
        else
            break;
    }
    resume = node;
    if (node == kVisible) return Result::Visible;
    if (node == kOccluded) return Result::Occluded;
    dvec3 c[8];
    for (int k = 0; k < 8; ++k) c[k] = cornerOf(lo, hi, k);
    // The box is hidden when its front faces are: each is tested as a polygon, split exactly where a
    // plane crosses it (a face is planar, so its corners bound it on either side of any plane).
    const uint32_t first = uint32_t(pool_.size());
    bool occ = true;
    for (int a = 0; a < 3 && occ; ++a) {
        if (reg[a] == 1) continue;
        const int k0 = (reg[a] == 2 ? 1 : 0) << a, b1 = 1 << ((a + 1) % 3), b2 = 1 << ((a + 2) % 3);
        for (int k : {k0, k0 | b1, k0 | b1 | b2, k0 | b2}) pool_.push_back({c[k], false});
        occ = occluded(node, Poly{first, 4}, mag);
        pool_.resize(first);
    }
    return occ ? Result::Occluded : Result::Partial;
}

OcclusionTree::Result OcclusionTree::test(const Box& world, int32_t& resume) {
    return testRelative(world.min - eye_, world.max - eye_, resume);
}

bool OcclusionTree::isOccluded(const Box& world) {
    int32_t r = root_;
    return test(world, r) == Result::Occluded;
}

}  // namespace sg
