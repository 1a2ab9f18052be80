#include "sg/build/PvsBuilder.h"

#include "nodes/Occluder.h"
#include "sg/scene/Scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sg {

namespace {
using P2 = glm::dvec2;
constexpr double kInfD = std::numeric_limits<double>::infinity();

double cross(const P2& o, const P2& a, const P2& b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Convex hull, counter-clockwise, of pts (reordered); collinear points dropped.
void hull(std::vector<P2>& pts, std::vector<P2>& out) {
    out.clear();
    std::sort(pts.begin(), pts.end(), [](const P2& a, const P2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    if (pts.size() < 3) {
        out = pts;
        return;
    }
    out.resize(2 * pts.size());
    size_t k = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        while (k >= 2 && cross(out[k - 2], out[k - 1], pts[i]) <= 0) --k;
        out[k++] = pts[i];
    }
    for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(out[k - 2], out[k - 1], pts[i]) <= 0) --k;
        out[k++] = pts[i];
    }
    out.resize(k - 1);
}

// Keeps the part of convex `poly` inside convex counter-clockwise `clip` (Sutherland-Hodgman).
void clipConvex(std::vector<P2>& poly, const std::vector<P2>& clip, std::vector<P2>& tmp) {
    for (size_t e = 0; e < clip.size() && !poly.empty(); ++e) {
        const P2 a = clip[e], b = clip[(e + 1) % clip.size()];
        tmp.clear();
        for (size_t i = 0; i < poly.size(); ++i) {
            const P2 p = poly[i], q = poly[(i + 1) % poly.size()];
            const double sp = cross(a, b, p), sq = cross(a, b, q);
            if (sp >= 0) tmp.push_back(p);
            if ((sp >= 0) != (sq >= 0)) tmp.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        poly.swap(tmp);
    }
}

// The x extent of convex `poly` on the line at y; false when the line misses it.
bool spanAt(const std::vector<P2>& poly, double y, double& lo, double& hi) {
    lo = kInfD;
    hi = -kInfD;
    for (size_t i = 0; i < poly.size(); ++i) {
        const P2 p = poly[i], q = poly[(i + 1) % poly.size()];
        if (y < std::min(p.y, q.y) || y > std::max(p.y, q.y)) continue;
        if (p.y == q.y) {
            lo = std::min({lo, p.x, q.x});
            hi = std::max({hi, p.x, q.x});
        } else {
            const double x = p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y);
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        }
    }
    return lo <= hi;
}

// A pixel index clamped to the map [0, res - 1] (projections may reach far beyond it).
int toPixel(double f, int res) { return f >= 0.0 ? int(std::min(f, double(res - 1))) : 0; }

struct Occ {
    std::vector<dvec3> v;  // world vertices (a box's 8 corners, or the polygon)
    Box box;
};

// One direction's map for the current cell; coordinates relative to the cell's centre.
struct DirMap {
    bool built = false, usable = false;
    double tP = 0.0;        // the plane's depth along the direction
    double ou = 0, ow = 0;  // the map's corner in the plane (u, w: the other two axes in order)
    double pu = 0, pw = 0;  // pixel size
    double nearest = 0.0;   // the nearest depth drawn
    std::vector<float> depth;
};

class Build {
public:
    Build(const Scene& s, const PvsBuilder::Options& o, PvsBuilder::Stats& st) : img_(s.image()), opt_(o), st_(st) {
        for (const FlatImage::OccluderRef& r : img_.occluders) {
            // One held by a PagedLOD's coarse level goes when its detail comes, one under a Switch or a mask goes
            // with them, and a generated one holds only for some eyes and frames (FlatImage::OccluderRef::
            // conditional): none is an occluder for every eye of a cell in every frame.
            if (!r.active || r.underPaged || r.conditional ||
                (img_.flags[r.entry] & (FlatImage::kEmpty | FlatImage::kInvalid)))
                continue;
            const auto* node = static_cast<const Occluder*>(r.node);
            const dmat4* m = r.matrix == ~0u ? nullptr : &img_.occluderMatrices[r.matrix];
            Occ oc;
            if (node->shape() == Occluder::Shape::Box) {
                const Box& b = node->box();
                for (int k = 0; k < 8; ++k) {
                    const dvec3 c(k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z);
                    oc.v.push_back(m ? dvec3(*m * dvec4(c, 1.0)) : c + r.shift);
                }
            } else {
                for (const dvec3& p : node->polygon()) oc.v.push_back(m ? dvec3(*m * dvec4(p, 1.0)) : p + r.shift);
            }
            for (const dvec3& p : oc.v) oc.box.expand(p);
            occs_.push_back(std::move(oc));
        }
    }

    void cell(PvsTable& t, size_t cell) {
        const Box cb = t.cellBox(cell);
        // Grown by a little more than rounding: an eye that cellAt() puts in this cell is inside.
        const double mag = std::max({std::abs(cb.min.x), std::abs(cb.min.y), std::abs(cb.min.z), std::abs(cb.max.x),
                                     std::abs(cb.max.y), std::abs(cb.max.z)});
        const double pad =
            1e-9 * mag + 1e-7 * std::max({cb.max.x - cb.min.x, cb.max.y - cb.min.y, cb.max.z - cb.min.z});
        centre_ = cb.center();
        half_ = cb.halfExtent() + pad;
        for (DirMap& d : dirs_) d.built = false;
        const uint32_t n = uint32_t(img_.size());
        for (uint32_t i = 0; i < n;) {
            const uint8_t fl = img_.flags[i];
            const NodeKind k = img_.kind[i];
            if (fl & (FlatImage::kEmpty | FlatImage::kNoTest)) {  // nothing drawn, or the billboard's test holds
                i = img_.end[i];
                continue;
            }
            // Never hidden themselves (their children are tested): bounds shared with the children, the
            // occlusion's own entries, paged nodes (their detail is another image), invalid bounds.
            if ((fl & FlatImage::kInvalid) || k == NodeKind::Transform || k == NodeKind::LOD ||
                k == NodeKind::Occluder || k == NodeKind::PagedLOD) {
                ++i;
                continue;
            }
            if (hidden(img_.box(i))) {
                t.setHidden(cell, i);
                st_.hidden++;
                i = img_.end[i];
            } else {
                ++i;
            }
        }
        st_.cellsComputed++;
    }

private:
    // Depth along direction dir (axis dir / 2, negative when odd) of a cell-relative point.
    static double depth(int dir, const dvec3& p) { return dir & 1 ? -p[dir / 2] : p[dir / 2]; }
    dvec3 corner(int k) const {
        return dvec3(k & 1 ? half_.x : -half_.x, k & 2 ? half_.y : -half_.y, k & 4 ? half_.z : -half_.z);
    }
    // A cell-relative point projected from cell corner c onto dir's plane at depth tP: (u, w).
    static P2 project(int dir, double tP, const dvec3& c, const dvec3& p) {
        const int a = dir / 2, u = (a + 1) % 3, w = (a + 2) % 3;
        const double tc = depth(dir, c), s = (tP - tc) / (depth(dir, p) - tc);
        return P2(c[u] + (p[u] - c[u]) * s, c[w] + (p[w] - c[w]) * s);
    }

    bool hidden(const Box& world) {
        const Box b{world.min - centre_, world.max - centre_};
        for (int dir = 0; dir < 6; ++dir) {
            const double cD = half_[dir / 2];
            const double bNear = dir & 1 ? -b.max[dir / 2] : b.min[dir / 2];
            if (!(bNear > cD + 1e-9 * (std::abs(bNear) + cD))) continue;  // not entirely beyond this face
            for (int nearPlane = 0; nearPlane < 2; ++nearPlane) {         // beyond all, beyond the largest
                if (opt_.plane != PvsBuilder::Plane::Both &&
                    (opt_.plane == PvsBuilder::Plane::BeyondLargest) != bool(nearPlane))
                    continue;
                DirMap& d = dirs_[2 * dir + nearPlane];
                if (!d.built) buildMap(dir, nearPlane, d);
                if (!d.usable) continue;
                st_.tests++;
                if (test(dir, d, b, bNear)) return true;
            }
        }
        return false;
    }

    void buildMap(int dir, bool nearPlane, DirMap& d) {
        d.built = true;
        d.usable = false;
        const int a = dir / 2, u = (a + 1) % 3, w = (a + 2) % 3;
        const double cD = half_[a], cNear = -half_[a];
        // Candidates: entirely beyond the face by the near clearance, and within the map's angles.
        cands_.clear();
        for (uint32_t k = 0; k < occs_.size(); ++k) {
            const Box ob{occs_[k].box.min - centre_, occs_[k].box.max - centre_};
            const double minT = dir & 1 ? -ob.max[a] : ob.min[a], maxT = dir & 1 ? -ob.min[a] : ob.max[a];
            if (!(minT > cD + opt_.maxNear)) continue;
            const double reach = opt_.maxTan * (maxT - cNear);
            const double gu = std::max({ob.min[u] - half_[u], -half_[u] - ob.max[u], 0.0});
            const double gw = std::max({ob.min[w] - half_[w], -half_[w] - ob.max[w], 0.0});
            if (gu > reach || gw > reach) continue;
            const dvec3 gap = glm::max(glm::max(ob.min - half_, -half_ - ob.max), dvec3(0.0));
            const dvec3 size = ob.max - ob.min;
            cands_.push_back({glm::dot(size, size) / std::max(glm::dot(gap, gap), 1e-12), k, minT, maxT});
        }
        if (cands_.empty() || opt_.maxOccluders == 0) return;
        const size_t keep = std::min<size_t>(cands_.size(), opt_.maxOccluders);
        auto byScore = [](const Cand& x, const Cand& y) {
            return x.score > y.score || (x.score == y.score && x.k < y.k);
        };
        auto byScoreRev = [&](const Cand& x, const Cand& y) { return byScore(y, x); };
        std::nth_element(cands_.begin(), cands_.begin() + ptrdiff_t(keep - 1), cands_.end(), byScore);
        // The plane: no occluder used may straddle it (the intersection of the corners' projections is the
        // extended projection only for an occluder entirely on one side). Just beyond the largest occluder
        // (the extended projections are tightest near the plane; straddling ones are dropped), or beyond
        // them all.
        double far = cD;
        if (nearPlane) {
            const Cand best = *std::max_element(cands_.begin(), cands_.begin() + ptrdiff_t(keep), byScoreRev);
            far = best.maxT;
        } else {
            for (size_t c = 0; c < keep; ++c) far = std::max(far, cands_[c].maxT);
        }
        d.tP = far + 0.01 * (far - cNear) + 1e-6;
        const double hu = half_[u] + opt_.maxTan * (d.tP - cNear), hw = half_[w] + opt_.maxTan * (d.tP - cNear);
        const int res = opt_.resolution;
        d.ou = -hu;
        d.ow = -hw;
        d.pu = 2.0 * hu / res;
        d.pw = 2.0 * hw / res;
        d.depth.assign(size_t(res) * res, std::numeric_limits<float>::infinity());
        d.nearest = kInfD;
        st_.maps++;
        for (size_t c = 0; c < keep; ++c) {
            const Occ& o = occs_[cands_[c].k];
            if (cands_[c].minT <= d.tP && cands_[c].maxT >= d.tP) continue;  // straddles the plane
            for (int k = 0; k < 8; ++k) {
                pts_.clear();
                for (const dvec3& p : o.v) pts_.push_back(project(dir, d.tP, corner(k), p - centre_));
                hull(pts_, k == 0 ? poly_ : hull_);
                if (k > 0) clipConvex(poly_, hull_, tmp_);
                if (poly_.size() < 3) break;
            }
            if (poly_.size() < 3) continue;
            float val = float(cands_[c].maxT);
            if (double(val) < cands_[c].maxT) val = std::nextafter(val, HUGE_VALF);
            if (drawInner(d, val)) {
                st_.occluders++;
                d.nearest = std::min(d.nearest, double(val));
                d.usable = true;
            }
        }
    }

    // Every pixel entirely inside poly_ keeps the nearer of its depth and val. False when none is.
    bool drawInner(DirMap& d, float val) {
        const int res = opt_.resolution;
        double y0 = kInfD, y1 = -kInfD;
        for (const P2& p : poly_) y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
        // Rows [fr0, fr1] lie within the polygon's y extent; clamped to the map only after that check.
        const double fr0 = std::ceil((y0 - d.ow) / d.pw), fr1 = std::floor((y1 - d.ow) / d.pw) - 1;
        if (!(fr0 <= fr1 && fr1 >= 0.0 && fr0 < res)) return false;
        bool any = false;
        for (int r = toPixel(fr0, res); r <= toPixel(fr1, res); ++r) {
            double a0, b0, a1, b1;
            if (!spanAt(poly_, d.ow + r * d.pw, a0, b0) || !spanAt(poly_, d.ow + (r + 1) * d.pw, a1, b1)) continue;
            const double fc0 = std::ceil((std::max(a0, a1) - d.ou) / d.pu),
                         fc1 = std::floor((std::min(b0, b1) - d.ou) / d.pu) - 1;
            if (!(fc0 <= fc1 && fc1 >= 0.0 && fc0 < res)) continue;
            float* row = &d.depth[size_t(r) * res];
            for (int c = toPixel(fc0, res); c <= toPixel(fc1, res); ++c) row[c] = std::min(row[c], val);
            any = true;
        }
        return any;
    }

    // The occludee b (cell-relative, nearest depth bNear along dir) against dir's map.
    bool test(int dir, const DirMap& d, const Box& b, double bNear) {
        // Depth margin: relative rounding, and 32 steps of a 24-bit depth buffer at the farthest distance.
        const dvec3 far = glm::max(glm::abs(b.min), glm::abs(b.max)) + half_;
        const double z2 = glm::dot(far, far);
        const double limit = bNear - 1e-6 * (std::abs(bNear) + std::sqrt(z2)) - 32.0 * z2 / (opt_.minNear * 16777216.0);
        if (!(d.nearest < limit)) return false;
        pts_.clear();
        for (int k = 0; k < 8; ++k)
            for (int j = 0; j < 8; ++j) {
                const dvec3 p(j & 1 ? b.max.x : b.min.x, j & 2 ? b.max.y : b.min.y, j & 4 ? b.max.z : b.min.z);
                pts_.push_back(project(dir, d.tP, corner(k), p));
            }
        hull(pts_, hull_);
        if (hull_.size() < 3) return false;
        // OUTER, grown by one pixel: every pixel within a pixel of the hull.
        const int res = opt_.resolution;
        const double m = std::max(d.pu, d.pw);
        double y0 = kInfD, y1 = -kInfD;
        for (const P2& p : hull_) y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
        const double fr0 = std::floor((y0 - m - d.ow) / d.pw), fr1 = std::floor((y1 + m - d.ow) / d.pw);
        if (!(fr0 >= 0.0 && fr1 < res)) return false;  // beyond the map (or not finite)
        for (int r = int(fr0); r <= int(fr1); ++r) {
            const double ya = std::max(d.ow + r * d.pw - m, y0), yb = std::min(d.ow + (r + 1) * d.pw + m, y1);
            double lo, hi, l2, h2;
            if (!spanAt(hull_, ya, lo, hi) || !spanAt(hull_, yb, l2, h2)) return false;  // cannot happen: be safe
            lo = std::min(lo, l2);
            hi = std::max(hi, h2);
            for (const P2& p : hull_)
                if (p.y >= ya && p.y <= yb) lo = std::min(lo, p.x), hi = std::max(hi, p.x);
            const double fc0 = std::floor((lo - m - d.ou) / d.pu), fc1 = std::floor((hi + m - d.ou) / d.pu);
            if (!(fc0 >= 0.0 && fc1 < res)) return false;
            const float* row = &d.depth[size_t(r) * res];
            for (int c = int(fc0); c <= int(fc1); ++c)
                if (!(double(row[c]) < limit)) return false;
        }
        return true;
    }

    const FlatImage& img_;
    const PvsBuilder::Options& opt_;
    PvsBuilder::Stats& st_;
    std::vector<Occ> occs_;
    dvec3 centre_{0.0}, half_{0.0};
    DirMap dirs_[12];  // per direction, the plane beyond all occluders and the one beyond the largest
    struct Cand {
        double score;
        uint32_t k;
        double minT, maxT;  // depth along the direction, cell-relative
    };
    std::vector<Cand> cands_;
    std::vector<P2> pts_, poly_, hull_, tmp_;
};
}  // namespace

PvsTable::Grid PvsBuilder::gridFor(const Options& o) {
    const Box& r = o.region;
    PvsTable::Grid g;
    for (int a = 0; a < 3; ++a) {
        const double ext = r.max[a] - r.min[a];
        if (!(ext >= 0.0) || !std::isfinite(ext) || !std::isfinite(r.min[a]) || !(o.cellSize[a] > 0.0) ||
            !std::isfinite(o.cellSize[a]))
            throw std::invalid_argument("PvsBuilder::gridFor(): the region must be a finite box and cell sizes > 0");
        const double n = std::max(1.0, std::ceil(ext / o.cellSize[a] - 1e-9));
        if (n > 1e6) throw std::invalid_argument("PvsBuilder::gridFor(): more than 1e6 cells along an axis");
        (a == 0 ? g.nx : a == 1 ? g.ny : g.nz) = uint32_t(n);
        g.origin[a] = r.min[a];
        g.cellSize[a] = ext > 0.0 ? ext / n : o.cellSize[a] * 1e-6;  // a flat region: thin cells
    }
    return g;
}

PvsTable PvsBuilder::build(const Scene& scene, const Options& o, Stats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    if (o.resolution < 16 || o.resolution > 8192)
        throw std::invalid_argument("PvsBuilder::build(): resolution " + std::to_string(o.resolution) +
                                    " is not in 16..8192");
    if (!(o.maxTan > 0.0) || !std::isfinite(o.maxTan))
        throw std::invalid_argument("PvsBuilder::build(): maxTan must be positive");
    PvsTable t(gridFor(o), scene.image(), o.minNear, o.maxNear);
    Stats local;
    Stats& st = stats ? *stats : local;
    st = Stats{};
    Build b(scene, o, st);
    std::vector<char> wanted(t.cellCount(), o.only.empty());
    for (const dvec3& p : o.only) {
        const long c = t.cellAt(p);
        if (c >= 0) wanted[size_t(c)] = 1;
    }
    for (size_t c = 0; c < t.cellCount(); ++c)
        if (wanted[c]) b.cell(t, c);
    st.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return t;
}

}  // namespace sg
