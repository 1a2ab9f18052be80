// OcclusionTree against a brute force: rays from the eye to points sampled over a box's surface, cast
// against every occluder. The tree may never cull a box with a visible sample (by isOccluded or by the
// hierarchical test) and must cull most hidden ones. The cases lean on the hard spots: the eye in an
// occluder's face plane or on an edge's line, touching and coplanar occluders, 1 mm and 10 km occluders,
// boxes touching an occluder's back face, in its front face's plane or at its shadow's edge, near planes,
// the two-level tree, and all of it again 10,000 km from the origin.
#include "sg/cull/OcclusionTree.h"
#include "testbed/Rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

using namespace sg;
using Result = OcclusionTree::Result;

namespace {

// ---- The brute force. Everything eye-relative: world coordinates near 1e7 minus the eye's are exact
// (Sterbenz), so it sees exactly the geometry the tree was given.
struct Occ {
    Box box;  // local when oriented
    bool oriented = false;
    dmat4 m{1.0};               // local to world (oriented boxes)
    std::vector<dvec3> poly{};  // non-empty: a convex polygon (world) instead of a box
};
struct View {
    dvec3 eye{0.0};
    std::vector<Occ> occs;  // in insertion order
    OcclusionTree::Options opts;
};

// A ray is blocked where it enters an occluder's interior (open box, open polygon) strictly before the
// sample and beyond the near plane, if any (only the parts of front faces beyond it are drawn). Grazing a
// face or an edge does not block, and an eye on or in a box sees through it (its faces are edge-on or
// back-facing): the strictest reference. Plain arrays, as this runs ~10^8 times, also unoptimized.
class Reference {
    struct Prep {
        bool poly = false, none = false;  // none: blocks nothing
        double lin[3][3], lo[3], hi[3];   // world to box frame; the box relative to the eye in that frame
        int n = 0;                        // polygon: plane nrm.p = nw, vertices a, inward edge normals en
        double nrm[3], nw, a[8][3], en[8][3];
    };
    const View& v_;
    std::vector<Prep> occ_;
    size_t last_ = 0;  // the occluder that blocked the previous sample is tried first
    static double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
    static bool blocks(const Prep& o, const double* s, double t0, double t1) {
        if (o.none) return false;
        if (o.poly) {
            const double ns = dot(o.nrm, s), t = ns == 0 ? kNaN : o.nw / ns;  // where it meets the plane
            if (!(t > t0 && t < t1)) return false;
            for (int i = 0; i < o.n; ++i) {
                const double d[3] = {s[0] * t - o.a[i][0], s[1] * t - o.a[i][1], s[2] * t - o.a[i][2]};
                if (!(dot(o.en[i], d) > 0)) return false;
            }
            return true;
        }
        double in = -kInf, out = kInf;  // the open interval of the ray inside the box
        for (int k = 0; k < 3; ++k) {   // (d == 0 inside the slab gives an infinite interval)
            const double d = dot(o.lin[k], s), a = o.lo[k] / d, b = o.hi[k] / d;
            if (d == 0 && !(o.lo[k] < 0 && o.hi[k] > 0)) return false;
            const double enter = a < b ? a : b, leave = a < b ? b : a;  // no std::min/max: calls when unoptimized
            in = enter > in ? enter : in, out = leave < out ? leave : out;
        }
        return in < out && in > t0 && in < t1;
    }

public:
    explicit Reference(const View& v) : v_(v) {
        for (const Occ& o : v.occs) {
            Prep p;
            if ((p.poly = !o.poly.empty())) {
                p.n = int(o.poly.size()), p.none = p.n > 8;
                dvec3 nrm(0.0);
                for (int i = 0; i < p.n; ++i) nrm += glm::cross(o.poly[i] - v.eye, o.poly[(i + 1) % p.n] - v.eye);
                for (int i = 0; i < p.n && i < 8; ++i) {
                    const dvec3 a = o.poly[i] - v.eye, en = glm::cross(nrm, o.poly[(i + 1) % p.n] - o.poly[i]);
                    for (int k = 0; k < 3; ++k) p.a[i][k] = a[k], p.en[i][k] = en[k], p.nrm[k] = nrm[k];
                }
                p.nw = glm::dot(nrm, o.poly[0] - v.eye);
            } else {
                const glm::dmat3 l = o.oriented ? glm::inverse(glm::dmat3(o.m)) : glm::dmat3(1.0);
                const dvec3 e = l * (v.eye - dvec3(o.m[3]));  // the eye in the box's frame
                for (int k = 0; k < 3; ++k) {
                    for (int c = 0; c < 3; ++c) p.lin[k][c] = l[c][k];
                    p.lo[k] = o.box.min[k] - e[k], p.hi[k] = o.box.max[k] - e[k];
                }
                p.none = glm::all(glm::lessThanEqual(o.box.min, e)) && glm::all(glm::lessThanEqual(e, o.box.max));
            }
            occ_.push_back(p);
        }
    }
    bool visible(const double* s) {    // s: the sample, eye-relative
        double t0 = 0, t1 = 1 - 1e-9;  // a blocker must lie strictly before the sample
        if (v_.opts.hasNear) {
            const double ns = glm::dot(v_.opts.nearPlane.n, dvec3(s[0], s[1], s[2])), d = v_.opts.nearPlane.d;
            if (ns > 0) t0 = std::max(0.0, -d / ns);
            if (ns < 0) t1 = std::min(t1, -d / ns);
            if (ns == 0 && d < 0) return true;
        }
        if (last_ < occ_.size() && blocks(occ_[last_], s, t0, t1)) return false;
        for (size_t i = 0; i < occ_.size(); ++i)
            if (i != last_ && blocks(occ_[i], s, t0, t1)) return last_ = i, false;
        return true;
    }
    // Finds a visible sample of the box: its 8 corners, then 3x3 points inside each face.
    bool visibleSample(const Box& b, dvec3* at = nullptr) {
        static const std::vector<dvec3> kAt = [] {  // the samples, as fractions of the box
            std::vector<dvec3> f;
            for (int k = 0; k < 8 + 6 * 9; ++k) {
                dvec3 p(k & 1, (k >> 1) & 1, (k >> 2) & 1);
                const int a = (k - 8) / 18, i = (k - 8) % 9;
                if (k >= 8)
                    p[a] = (k - 8) / 9 % 2, p[(a + 1) % 3] = (i / 3 + 1) / 4.0, p[(a + 2) % 3] = (i % 3 + 1) / 4.0;
                f.push_back(p);
            }
            return f;
        }();
        const dvec3 lo = b.min - v_.eye, ext = b.max - b.min;
        const double* f = &kAt[0].x;
        for (size_t k = 0; k < (ext == dvec3(0.0) ? 1 : kAt.size()); ++k, f += 3) {  // a point: one sample
            const double s[3] = {lo.x + ext.x * f[0], lo.y + ext.y * f[1], lo.z + ext.z * f[2]};
            if (!visible(s)) continue;
            if (at) *at = v_.eye + dvec3(s[0], s[1], s[2]);
            return true;
        }
        return false;
    }
};
bool visibleSample(const View& v, const Box& b, dvec3* at = nullptr) { return Reference(v).visibleSample(b, at); }

void insert(OcclusionTree& t, const Occ& o) {
    if (!o.poly.empty()) t.insertPolygon(o.poly.data(), o.poly.size());
    if (o.poly.empty()) t.insertBox(o.box, o.oriented ? &o.m : nullptr);
}
Box worldBounds(const Occ& o) {
    Box b = o.oriented ? transformBox(o.m, o.box) : o.box;
    for (const dvec3& p : o.poly) b.expand(p);
    return b;
}
Occ polygon(std::vector<dvec3> p) { return Occ{Box{}, false, dmat4(1.0), std::move(p)}; }

std::string describe(const View& v, const Box& b, const dvec3& at) {
    std::string s;
    char buf[160];
    auto add = [&](const char* tag, const dvec3& p) {
        std::snprintf(buf, sizeof buf, "%s(%.17g, %.17g, %.17g)", tag, p.x, p.y, p.z);
        s += buf;
    };
    add("eye ", v.eye);
    std::snprintf(buf, sizeof buf, "\n cap %d, screenSplits %d, tanX %.17g, tanY %.17g, viewToWorld", int(v.opts.cap),
                  v.opts.screenSplits, v.opts.tanX, v.opts.tanY);
    s += buf;
    for (int c = 0; c < 3; ++c) add(" ", v.opts.viewToWorld[c]);
    std::snprintf(buf, sizeof buf, "\n near plane d %.17g, n", v.opts.nearPlane.d);
    if (v.opts.hasNear) s += buf, add(" ", v.opts.nearPlane.n);
    for (const Occ& o : v.occs) {
        s += o.poly.empty() ? (o.oriented ? "\n oriented box " : "\n box ") : "\n polygon";
        if (o.poly.empty()) add("", o.box.min), add(" - ", o.box.max);
        for (const dvec3& p : o.poly) add(" ", p);
        for (int c = 0; c < 4 && o.oriented; ++c) add(" column ", dvec3(o.m[c]));
    }
    add("\n test box ", b.min), add(" - ", b.max), add("\n visible sample ", at);
    return s;
}

// ---- Random cases. splitmix64: cheap to seed per case, so any case reruns alone from its seed.
using Rng = scenes::BasicRng<scenes::SplitMix64>;
// Coordinates on a 2^-28 grid and below 2^24: moved 1e7 away they stay exact, the same geometry.
double q(double x) { return std::round(x * 0x1p28) * 0x1p-28; }
dvec3 q(const dvec3& v) { return dvec3(q(v.x), q(v.y), q(v.z)); }

enum Family { General, EyeOnFacePlane, EdgeThroughEye, RowOfBuildings, Tiny, Huge, Contact, kFamilies };
const char* kFamilyNames[] = {"general",       "eye-on-face-plane", "edge-through-eye",  "row-of-buildings",
                              "1mm-occluders", "10km-occluders",    "back/front-contact"};

struct Case {
    View v;
    std::vector<Box> tests;  // a parent, then its child, and so on
    void shift(const dvec3& off) {
        v.eye += off;
        for (Occ& o : v.occs) {
            if (o.oriented) o.m[3] += dvec4(off, 0.0);
            if (!o.oriented) o.box.min += off, o.box.max += off;
            for (dvec3& p : o.poly) p += off;
        }
        for (Box& b : tests) b.min += off, b.max += off;
    }
};

// A test box near occluder o: behind it as seen from the eye (kind 0 to 2), touching its back face (3), in
// its front face's plane (4), or within grid steps of its shadow's edge (5).
Box testBox(const dvec3& eye, const Occ& o, int kind, Rng& r) {
    const Box w = worldBounds(o);
    const dvec3 ext = w.max - w.min, out = glm::max(w.min - eye, eye - w.max);   // out: how far outside, per axis
    const int e = out.x >= std::max(out.y, out.z) ? 0 : out.y >= out.z ? 1 : 2;  // contact boxes: across this axis
    if ((kind == 3 || kind == 4) && o.poly.empty() && !o.oriented && out[e] > 0) {
        const double dir = eye[e] < w.min[e] ? 1 : -1;  // away from the eye
        const double plane = (kind == 3) == (dir > 0) ? w.max[e] : w.min[e];
        Box b;
        for (int k = 0; k < 3; ++k) {
            const double u = r.uniform(-0.3, 1.3), v = r.uniform(-0.3, 1.3);
            b.min[k] = q(w.min[k] + ext[k] * std::min(u, v)), b.max[k] = q(w.min[k] + ext[k] * std::max(u, v));
        }
        // From the back face away from the eye; from the front plane away, toward the eye, or flat in it.
        const double end = plane + dir * (kind == 3 ? 1 : r.below(3) - 1) * q(ext[e] * r.uniform(0.1, 2.0));
        b.min[e] = std::min(plane, end), b.max[e] = std::max(plane, end);
        return b;
    }
    if (kind == 5) {  // a point of an occluder edge, pushed back from the eye, onto the grid
        dvec3 p;
        if (!o.poly.empty()) {
            const size_t i = size_t(r.below(int(o.poly.size())));
            p = glm::mix(o.poly[i], o.poly[(i + 1) % o.poly.size()], r.uniform(0, 1));
        } else {
            const int ax = r.below(3);
            for (int k = 0; k < 3; ++k)
                p[k] = k == ax ? r.uniform(o.box.min[k], o.box.max[k]) : r.below(2) ? o.box.max[k] : o.box.min[k];
            if (o.oriented) p = dvec3(o.m * dvec4(p, 1.0));
        }
        const dvec3 lo = q(eye + (p - eye) * r.uniform(1.2, 2.5));
        return Box{lo, lo + dvec3(r.below(3), r.below(3), r.below(3)) * 0x1p-28};
    }
    const dvec3 centre =
        eye + (w.min + ext * dvec3(r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1)) - eye) * r.uniform(1.0, 2.5);
    const dvec3 half =
        dvec3(r.uniform(0.05, 0.8), r.uniform(0.05, 0.8), r.uniform(0.05, 0.8)) * ((ext.x + ext.y + ext.z) / 6);
    return Box{q(centre - half), q(centre + half)};
}

Case makeCase(int fam, int index, Rng& r) {
    Case c;
    View& v = c.v;
    const double s = fam == Tiny ? 2e-4 : fam == Huge ? 1e3 : 1.0;  // occluders ~1 mm, ~10 km across
    v.eye = q(dvec3(r.uniform(-5, 5), r.uniform(-5, 5), r.uniform(-5, 5)) * s);
    const int a = r.below(3), b = (a + 1) % 3, up = (a + 2) % 3;  // a: the main view axis
    const double sign = r.below(2) ? 1 : -1;
    const int n = fam == RowOfBuildings ? 2 + r.below(3) : 1 + r.below(3);
    double x = q(v.eye[b] + r.uniform(-15, -3) * s);
    const double front = v.eye[a] + sign * r.uniform(6, 20) * s, depth = r.uniform(2, 8) * s,
                 ground = q(v.eye[up] - r.uniform(0, 5) * s);
    for (int k = 0; k < n && fam == RowOfBuildings; ++k) {  // shared side faces, one front plane, some storeys
        const double w = q(r.uniform(1, 6) * s), top = q(ground + r.uniform(3, 12) * s);
        const double back = front + sign * (r.below(2) ? depth : r.uniform(2, 8) * s);
        Box bb;
        bb.min[a] = q(std::min(front, back)), bb.max[a] = q(std::max(front, back));
        bb.min[b] = x, bb.max[b] = x += w, bb.min[up] = ground, bb.max[up] = top;
        v.occs.push_back(Occ{bb});
        if (r.below(3) == 0) bb.min[up] = top, bb.max[up] = q(top + r.uniform(1, 4) * s), v.occs.push_back(Occ{bb});
    }
    for (int k = 0; k < n && fam != RowOfBuildings; ++k) {
        dvec3 ctr = v.eye, h = q(dvec3(r.uniform(0.5, 6), r.uniform(0.5, 6), r.uniform(0.5, 6)) * s);
        ctr[a] += sign * r.uniform(8, 40) * s, ctr[b] += r.uniform(-10, 10) * s, ctr[up] += r.uniform(-10, 10) * s;
        ctr = q(ctr);
        const int kind = fam == EyeOnFacePlane || fam == EdgeThroughEye ? 0 : r.below(20);
        if (kind < 14) {  // 14 in 20 boxes, 3 oriented boxes, 3 convex polygons
            Box bb{ctr - h, ctr + h};
            // The eye in the plane of a side face, or (two sides) on the line of an edge.
            for (int e : {b, up})
                if ((fam == EyeOnFacePlane && e == b) || fam == EdgeThroughEye)
                    (ctr[e] >= v.eye[e] ? bb.min[e] : bb.max[e]) = v.eye[e];
            v.occs.push_back(Occ{bb});
        } else if (kind < 17) {
            const dvec3 axis = glm::normalize(dvec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(0.1, 1)));
            v.occs.push_back(
                Occ{Box{-h, h}, true, glm::rotate(glm::translate(dmat4(1.0), ctr), r.uniform(0, 6.3), axis)});
        } else {  // a 3- to 6-gon in an axis plane (planar whatever the rounding)
            const int m = 3 + r.below(4), pa = r.below(2) ? a : r.below(3);
            const double rad = r.uniform(1, 6) * s, phase = r.uniform(0, 6.3), step = 6.283185307179586 / m;
            std::vector<dvec3> p(m, ctr);
            for (int i = 0; i < m; ++i)
                p[i][(pa + 1) % 3] += rad * std::cos(phase + step * i),
                    p[i][(pa + 2) % 3] += rad * std::sin(phase + step * i), p[i] = q(p[i]);
            v.occs.push_back(polygon(p));
        }
    }
    std::vector<std::pair<double, size_t>> order;  // nearest first, as the cull inserts them
    for (size_t k = 0; k < v.occs.size(); ++k) {
        const Box w = worldBounds(v.occs[k]);
        order.emplace_back(glm::length(glm::clamp(v.eye, w.min, w.max) - v.eye), k);
    }
    std::sort(order.begin(), order.end());
    std::vector<Occ> sorted;
    for (const auto& o : order) sorted.push_back(v.occs[o.second]);
    v.occs.swap(sorted);
    // A share with the two-level tree and a share with a near plane; the view looks along the main axis.
    dvec3 view(0.0), side(0.0);
    view[a] = sign, side[b] = 1;
    if (index % 4 == 1) {
        v.opts.screenSplits = 2 + (index / 4) % 2, v.opts.viewToWorld = glm::dmat3(side, glm::cross(side, view), -view);
        v.opts.tanX = r.uniform(0.3, 1.5), v.opts.tanY = v.opts.tanX * 0.75;
    }
    if (index % 8 == 3) v.opts.hasNear = true, v.opts.nearPlane = Plane{view, -r.uniform(0.1, 12) * s};
    for (int i = 0; i < 2; ++i) {  // two parents, each with a random sub-box as its child
        const Box p =
            testBox(v.eye, v.occs[r.below(int(v.occs.size()))], fam == Contact ? 3 + r.below(2) : r.below(6), r);
        Box ch;
        for (int j = 0; j < 3; ++j) {
            const double u = r.uniform(0, 1), w = r.uniform(0, 1), e = p.max[j] - p.min[j];
            ch.min[j] = std::clamp(q(p.min[j] + e * std::min(u, w)), p.min[j], p.max[j]);
            ch.max[j] = std::clamp(q(p.min[j] + e * std::max(u, w)), ch.min[j], p.max[j]);
        }
        c.tests.push_back(p), c.tests.push_back(ch);
    }
    return c;
}

struct Tally {
    long cases = 0, boxes = 0, culled = 0, hidden = 0, wrong = 0;
};

}  // namespace

TEST(OcclusionTree, NeverCullsAVisibleSampleAndCullsHiddenBoxes) {
    constexpr int kPerVariant = 7143;  // x 7 families x (near the origin, 10,000 km away)
    Tally fam[kFamilies], opt[3], all;
    const char* kOptNames[3] = {"one-level", "two-level", "near plane"};
    long inconsistent = 0;
    std::string firstWrong;  // the first few per family, as reproducers
    OcclusionTree tree;
    for (int f = 0; f < kFamilies; ++f)
        for (int far = 0; far < 2; ++far)
            for (int i = 0; i < kPerVariant; ++i) {
                const uint64_t seed = uint64_t(f) * 1000003 + uint64_t(i);
                Rng r{seed};
                Case c = makeCase(f, i, r);
                if (far) c.shift(dvec3(1e7, -1e7, 3e6));
                const View& v = c.v;
                tree.reset(v.eye, v.opts);
                for (const Occ& o : v.occs) insert(tree, o);
                Reference ref(v);
                Tally* tallies[3] = {&fam[f], &opt[v.opts.hasNear ? 2 : v.opts.screenSplits > 0], &all};
                for (Tally* t : tallies) ++t->cases;
                auto check = [&](const Box& b, bool culled, const char* what) {
                    dvec3 at(0.0);
                    const bool vis = ref.visibleSample(b, &at);
                    for (Tally* t : tallies)
                        ++t->boxes, t->culled += culled, t->hidden += !vis, t->wrong += culled && vis;
                    if (culled && vis && fam[f].wrong <= 3)
                        firstWrong += std::string(kFamilyNames[f]) + " seed " + std::to_string(seed) +
                                      (far ? " far " : " ") + what + "\n " + describe(v, b, at) + "\n";
                };
                for (size_t p = 0; p < c.tests.size(); p += 2) {
                    int32_t resume = tree.root();
                    const Result rp = tree.test(c.tests[p], resume);
                    const bool iso = tree.isOccluded(c.tests[p]);
                    inconsistent += iso != (rp == Result::Occluded);
                    check(c.tests[p], iso || rp == Result::Occluded, "parent");
                    // The child skips its test on Visible, is culled on Occluded, resumes on Partial.
                    const Box& child = c.tests[p + 1];
                    int32_t r2 = resume;
                    check(child,
                          rp == Result::Occluded || (rp == Result::Partial && tree.test(child, r2) == Result::Occluded),
                          "child");
                    if (rp == Result::Visible) inconsistent += tree.isOccluded(child);  // nothing inside is occluded
                }
            }
    auto print = [](const char* name, const Tally& t) {
        std::printf("%-20s cases %6ld boxes %7ld hidden %7ld culled %7ld (%.0f%% of hidden)\n", name, t.cases, t.boxes,
                    t.hidden, t.culled, 100.0 * t.culled / std::max(1L, t.hidden));
        EXPECT_GT(t.culled, t.hidden / 5) << name << ": too few hidden boxes culled";
    };
    for (int f = 0; f < kFamilies; ++f) print(kFamilyNames[f], fam[f]);
    for (int k = 0; k < 3; ++k) print(kOptNames[k], opt[k]);
    print("total", all);
    EXPECT_GE(all.cases, 100000);
    EXPECT_GE(all.culled, 100000);
    EXPECT_EQ(all.wrong, 0) << "boxes culled with a visible sample, the first per family:\n" << firstWrong;
    EXPECT_EQ(inconsistent, 0) << "isOccluded and test() disagree, or a Visible box holds an occluded one";
}

// Per region, the loop must be the box edges with exactly one of their two faces toward the eye.
TEST(OcclusionTree, SilhouetteTableIsTheOutline) {
    for (int r = 0; r < 27; ++r) {
        const int reg[3] = {r % 3, r / 3 % 3, r / 9};
        if (r == 13) continue;  // inside
        dvec3 eye;              // a representative eye for the region, the box being [0,1]^3
        for (int k = 0; k < 3; ++k) eye[k] = reg[k] == 0 ? -1.0 : reg[k] == 1 ? 0.5 : 2.0;
        auto faces = [&](int axis, int side) { return side ? eye[axis] > 1 : eye[axis] < 0; };
        std::set<std::pair<int, int>> want, got;
        for (int c = 0; c < 8; ++c)
            for (int k = 0; k < 3; ++k) {  // the edge from corner c along k, where faces across k1 and k2 meet
                const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
                if (!(c >> k & 1) && faces(k1, c >> k1 & 1) != faces(k2, c >> k2 & 1)) want.insert({c, c | 1 << k});
            }
        uint8_t out[6] = {};
        const int n = OcclusionTree::silhouette(reg[0], reg[1], reg[2], out);
        ASSERT_EQ(n, (reg[0] != 1) + (reg[1] != 1) + (reg[2] != 1) == 1 ? 4 : 6) << "region " << r;
        for (int i = 0; i < n; ++i) {
            const int a = out[i], b = out[(i + 1) % n];
            EXPECT_TRUE(a < 8 && __builtin_popcount(unsigned(a ^ b)) == 1) << "region " << r << ": " << a << ", " << b;
            got.insert({std::min(a, b), std::max(a, b)});
        }
        EXPECT_EQ(got, want) << "region " << r;
    }
}

const dvec3 kOrigins[2] = {dvec3(0.0), dvec3(1e7, -1e7, 3e6)};

// A box behind the seam of two walls is hidden by both only: walls as touching boxes, and as their front
// faces (polygons, overlapping by a millimetre: edge planes are narrowed by the margin, so polygons that
// merely share an edge leave a crack between their shadows).
TEST(OcclusionTree, NeighboursTogetherHideWhatNeitherHidesAlone) {
    for (const dvec3& off : kOrigins)
        for (bool poly : {false, true}) {
            const Box a{off + dvec3(-2, 10, -1), off + dvec3(0, 11, 1)};
            const Box b{off + dvec3(poly ? -0.001 : 0.0, 10, -1), off + dvec3(2, 11, 1)};
            const Box t{off + dvec3(-1, 20, -0.5), off + dvec3(1, 21, 0.5)};
            auto occ = [&](const Box& x) {
                const dvec3 lo = x.min, hi(x.max.x, x.min.y, x.max.z);
                return poly ? polygon({lo, dvec3(hi.x, lo.y, lo.z), hi, dvec3(lo.x, lo.y, hi.z)}) : Occ{x};
            };
            const std::vector<Occ> sets[4] = {{occ(a), occ(b)}, {occ(b), occ(a)}, {occ(a)}, {occ(b)}};
            for (int k = 0; k < 4; ++k) {
                const View v{off + dvec3(0.25, 0.125, 0.0625), sets[k], {}};
                ASSERT_EQ(visibleSample(v, t), k >= 2) << "set " << k;  // the setup itself
                OcclusionTree tree;
                tree.reset(v.eye, v.opts);
                for (const Occ& o : v.occs) insert(tree, o);
                EXPECT_EQ(tree.isOccluded(t), k < 2)
                    << "set " << k << (poly ? ", polygons" : ", boxes") << (off.x ? ", far" : "");
            }
        }
}

// The paper's cap, a plane through the box centre facing the eye, also takes in the space just in front
// of a face that recedes past that plane: a long box seen at a grazing angle shows it.
TEST(OcclusionTree, CenterPlaneCapIsNotConservative) {
    bool found = false;
    for (uint64_t seed = 1; seed <= 20000 && !found; ++seed) {
        Rng r{seed};
        const double x0 = r.uniform(-5, 10), y0 = r.uniform(2, 8), len = r.uniform(10, 60), z = r.uniform(1, 4);
        View v{dvec3(0.0), {Occ{Box{dvec3(x0, y0, -z), dvec3(x0 + len, y0 + r.uniform(0.5, 3), z)}}}, {}};
        OcclusionTree front, centre;
        front.reset(v.eye, v.opts), insert(front, v.occs[0]);
        v.opts.cap = OccluderCap::CenterPlane, centre.reset(v.eye, v.opts), insert(centre, v.occs[0]);
        for (int i = 0; i < 8 && !found; ++i) {  // small boxes just in front of the long face
            const dvec3 c(x0 + r.uniform(0, len), y0 - r.uniform(0.02, 1), r.uniform(-z, z));
            Box t{c - r.uniform(0.01, 0.3), c + r.uniform(0.01, 0.3)};
            t.max.y = std::min(t.max.y, y0 - 0.01);
            dvec3 at;
            if (!centre.isOccluded(t) || !visibleSample(v, t, &at)) continue;
            found = true;
            std::printf("the centre-plane cap culls a visible box (seed %d):\n %s\n", int(seed),
                        describe(v, t, at).c_str());
            EXPECT_FALSE(front.isOccluded(t));
        }
    }
    EXPECT_TRUE(found);
}

// Occluder parts nearer than the near plane are clipped away when drawn: they must not occlude.
TEST(OcclusionTree, NearPlaneClipsOccluders) {
    for (const dvec3& off : kOrigins) {
        auto at = [&](double x, double y, double z) { return off + dvec3(x, y, z); };
        // Cut: its front face (y = 0.5) is clipped away, its side face x = -1 is drawn for y in [1, 4].
        const Box cut{at(-3, 0.5, -1), at(-1, 4, 1)}, beyond{at(-3, 2, -1), at(-1, 4, 1)},
            nearer{at(-3, 0.25, -1), at(-1, 0.75, 1)};
        const Box through{at(-25, 8, -0.3), at(-24, 8.5, 0.3)};  // behind the clipped-away face only
        const Box behind{at(-4.2, 8, -0.3), at(-3.8, 9, 0.3)};   // behind the drawn part of the side face
        View v{off, {Occ{cut}}, {}}, noNear = v;
        v.opts.hasNear = true, v.opts.nearPlane = Plane{dvec3(0, 1, 0), -1.0};  // y >= 1 is drawn
        ASSERT_FALSE(visibleSample(noNear, through));
        ASSERT_TRUE(visibleSample(v, through));
        ASSERT_FALSE(visibleSample(v, behind));
        auto culls = [&](const OcclusionTree::Options& o, const Box& occ, const Box& t) {
            OcclusionTree tree;
            tree.reset(v.eye, o);
            tree.insertBox(occ);
            return tree.isOccluded(t);
        };
        EXPECT_TRUE(culls(noNear.opts, cut, through));
        EXPECT_FALSE(culls(v.opts, cut, through));
        EXPECT_TRUE(culls(v.opts, cut, behind));
        EXPECT_TRUE(culls(v.opts, beyond, behind));
        EXPECT_FALSE(culls(v.opts, nearer, behind));
        EXPECT_FALSE(culls(v.opts, nearer, through));
    }
}

// Degenerate and non-finite input is refused or harmless; what follows still culls, and only the hidden.
TEST(OcclusionTree, DegenerateInputNeverCrashesOrOverCulls) {
    for (const dvec3& off : kOrigins) {
        auto at = [&](double x, double y, double z) { return off + dvec3(x, y, z); };
        OcclusionTree tree;
        tree.reset(off, {});
        EXPECT_FALSE(tree.insertBox(Box{}));
        EXPECT_FALSE(tree.insertBox(Box{at(1, 10, 1), at(-1, 11, -1)}));  // inverted
        EXPECT_FALSE(tree.insertBox(Box{at(-1, -1, -1), at(1, 1, 1)}));   // the eye inside
        for (const Box& b :
             {Box{at(3, 10, 3), at(3, 10, 3)}, Box{at(-3, 10, 3), at(-1, 10, 3)},  // a point, a segment
              Box{at(0, -1, -1), at(2, 1, 1)}, Box{at(0, 0, 0), at(1, 1, 1)}})     // the eye on a face, a corner
            tree.insertBox(b);
        const std::vector<dvec3> polys[] = {
            {at(-5, -5, 0), at(5, -5, 0), at(5, 5, 0), at(-5, 5, 0)},  // edge-on, around the eye
            {at(5, -1, 0), at(7, -1, 0), at(7, 1, 0), at(5, 1, 0)},    // edge-on, beside it
            {at(0, 10, 0), at(1, 10, 1), at(2, 10, 2)},                // collinear
            {at(0, 10, 0), at(0, 10, 0), at(1, 10, 0), at(1, 10, 0)},  // repeated points
            {at(0, 10, 0), at(1, 10, 1)},
            {at(0, 10, 0)},
            {}};
        for (const auto& p : polys) tree.insertPolygon(p.empty() ? nullptr : p.data(), p.size());
        for (double bad : {kNaN, kInf, -kInf}) {
            dmat4 m = glm::translate(dmat4(1.0), at(0, 20, 0));
            m[1][2] = bad;
            const dvec3 tri[3] = {at(-1, 10, -1), at(1, 10, bad), at(0, 10, 1)};
            tree.insertBox(Box{at(bad, 10, -1), at(1, 11, 1)}), tree.insertBox(Box{dvec3(-kInf), dvec3(kInf)});
            tree.insertBox(Box{dvec3(-1), dvec3(1)}, &m), tree.insertPolygon(tri, 3);
        }
        // A flat box occludes as its rectangle; a wall after all that still works.
        const Box flat{at(-2, 10, -2), at(2, 10, 2)}, wall{at(-10, 30, -10), at(10, 31, 10)};
        tree.insertBox(flat), tree.insertBox(wall);
        const View real{off, {polygon({flat.min, at(2, 10, -2), flat.max, at(-2, 10, 2)}), Occ{wall}}, {}};
        Reference ref(real);
        Rng r{7};
        long culled = 0, wrong = 0;
        for (int i = 0; i < 3000; ++i) {  // boxes of every size down to points, some around the eye
            const dvec3 c = at(r.uniform(-12, 12), r.uniform(-5, 60), r.uniform(-12, 12));
            const dvec3 h(i % 3 ? r.uniform(0, 2) : 0.0, i % 5 ? r.uniform(0, 2) : 0.0, r.uniform(0, 2));
            const Box t{c - h, c + h};
            dvec3 sample;
            const bool occluded = tree.isOccluded(t), seen = occluded && ref.visibleSample(t, &sample);
            culled += occluded, wrong += seen;
            if (seen && wrong == 1) ADD_FAILURE() << describe(real, t, sample);
        }
        EXPECT_EQ(wrong, 0);
        EXPECT_GT(culled, 100);
        for (double bad : {kNaN, kInf, -kInf}) {
            for (const Box& t : {Box{at(bad, 40, 0), at(1, 41, 1)}, Box{at(0, 40, 0), at(1, bad, 1)},
                                 Box{dvec3(-kInf), dvec3(kInf)}}) {
                int32_t resume = tree.root();
                EXPECT_FALSE(tree.isOccluded(t));
                EXPECT_NE(tree.test(t, resume), Result::Occluded);
            }
            OcclusionTree eyeless;  // an eye that is not finite: nothing is occluded
            eyeless.reset(at(bad, 0, 0), {});
            eyeless.insertBox(wall);
            EXPECT_FALSE(eyeless.isOccluded(Box{at(-1, 40, -1), at(1, 41, 1)}));
        }
    }
}
