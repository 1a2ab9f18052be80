#include "sg/cull/OcclusionMap.h"

#include "sg/core/Camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sg {

namespace {
constexpr float kInfF = std::numeric_limits<float>::infinity();

// The corners of face (axis a, side s) of a box with corners indexed by bits (x, y, z), in order around it.
void faceCorners(int a, int s, int out[4]) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const int base = s << a;
    out[0] = base;
    out[1] = base | (1 << b);
    out[2] = base | (1 << b) | (1 << c);
    out[3] = base | (1 << c);
}

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }
}  // namespace

OcclusionMap::Options OcclusionMap::optionsFor(const Camera& cam, const OcclusionSettings& s) {
    s.validate("OcclusionMap::optionsFor()");
    Options o;
    o.width = s.homWidth;
    o.height = s.homHeight;
    o.opacity = float(s.homOpacity);
    // A 64th of a screen pixel: the rasterizer snaps vertices to 1/256 pixel, occluder and occludee alike.
    o.marginX = (1.0 / 64.0) * double(o.width) / double(cam.width());
    o.marginY = (1.0 / 64.0) * double(o.height) / double(cam.height());
    // A 24-bit depth buffer separates depths that differ by z^2 / (near 2^24): keep 8 steps clear of it. A float
    // reverse-Z buffer's interpolation errs as much on a triangle reaching the near plane (architecture.md, Depth).
    o.depthMargin = 8.0 / (cam.nearDistance() * 16777216.0);
    return o;
}

void OcclusionMap::reset(const Camera& cam, const Options& o) {
    if (opacity_.empty() || o.width != opt_.width || o.height != opt_.height) {
        opacity_.clear();
        depth_.clear();
        w_.clear();
        h_.clear();
        for (int w = o.width, h = o.height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
            w_.push_back(w);
            h_.push_back(h);
            opacity_.emplace_back(size_t(w) * size_t(h), 0.0f);
            depth_.emplace_back(size_t(w) * size_t(h), 0.0f);
            if (w == 1 && h == 1) break;
        }
    }
    opt_ = o;
    viewProj_ = cam.projection() * cam.viewRotation();
    near_ = cam.eyePlanes()[4];
    near_.d -= 1e-5 * cam.nearDistance();  // what lies within rounding of the near plane may be clipped
    std::fill(opacity_[0].begin(), opacity_[0].end(), 0.0f);
    std::fill(depth_[0].begin(), depth_[0].end(), 0.0f);  // nothing covered has no depth
    covered_ = 0;
}

float OcclusionMap::farDepth(double w) const {
    const double d = w * (1.0 + 1e-6) + opt_.depthMargin * w * w;
    float f = float(d);
    if (double(f) < d) f = std::nextafter(f, kInfF);
    return f;
}

bool OcclusionMap::project(const dvec3* v, size_t n, std::vector<Pt>& out) {
    // Sutherland-Hodgman against the near plane (the GPU draws nothing nearer).
    clip_.clear();
    for (size_t k = 0; k < n; ++k) {
        const dvec3& a = v[k];
        const dvec3& b = v[(k + 1) % n];
        const double da = near_.distance(a), db = near_.distance(b);
        if (da >= 0) clip_.push_back(a);
        if ((da >= 0) != (db >= 0)) clip_.push_back(a + (b - a) * (da / (da - db)));
    }
    if (clip_.size() < 3) return false;
    out.clear();
    for (const dvec3& p : clip_) {
        const dvec4 c = viewProj_ * dvec4(p, 1.0);
        if (!(c.w > 0.0)) return false;  // a projection where near does not mean in front: not used
        out.push_back({(c.x / c.w * 0.5 + 0.5) * opt_.width, (c.y / c.w * 0.5 + 0.5) * opt_.height});
    }
    return true;
}

bool OcclusionMap::rasterize(std::vector<Pt>& poly, float depth) {
    const size_t n = poly.size();
    if (n < 3 || n > 32) return false;
    double area = 0.0;
    for (size_t k = 0; k < n; ++k) area += cross(poly[k].x, poly[k].y, poly[(k + 1) % n].x, poly[(k + 1) % n].y);
    if (!(std::abs(area) > 1e-12) || !std::isfinite(area)) return false;
    if (area < 0) std::reverse(poly.begin(), poly.end());  // counter-clockwise: inside is to the left
    // Edge k: e(X, Y) = a X + b Y + c >= 0 inside. A pixel [x, x+1] x [y, y+1] is inside when its worst
    // corner is, by the margin: a x + min(a, 0) + b y + min(b, 0) + c >= m.
    struct Edge {
        double a, b, c, m;
    };
    Edge edges[32];
    size_t ne = 0;
    double ylo = 1e300, yhi = -1e300;
    for (size_t k = 0; k < n; ++k) {
        const Pt& p = poly[k];
        const Pt& q = poly[(k + 1) % n];
        const double a = -(q.y - p.y), b = q.x - p.x;
        if (a == 0.0 && b == 0.0) continue;
        edges[ne++] = {a, b, -(a * p.x + b * p.y), std::abs(a) * opt_.marginX + std::abs(b) * opt_.marginY};
        ylo = std::min(ylo, p.y);
        yhi = std::max(yhi, p.y);
    }
    if (ne < 3) return false;
    const int W = opt_.width, H = opt_.height;
    const int y0 = std::max(0, int(std::ceil(std::max(ylo, -1.0)))), y1 = std::min(H - 1, int(std::floor(yhi)) - 1);
    float* opa = opacity_[0].data();
    float* dep = depth_[0].data();
    bool any = false;
    for (int y = y0; y <= y1; ++y) {
        double xlo = 0.0, xhi = double(W - 1);
        for (size_t k = 0; k < ne; ++k) {
            const Edge& e = edges[k];
            const double rest = e.b * y + std::min(e.b, 0.0) + e.c - e.m;  // need a x + min(a, 0) + rest >= 0
            if (e.a > 0)
                xlo = std::max(xlo, -rest / e.a);
            else if (e.a < 0)
                xhi = std::min(xhi, (-rest - e.a) / e.a);  // a (x + 1) + rest >= 0, a < 0
            else if (rest < 0)
                xhi = -1.0;
        }
        if (!(xlo <= xhi)) continue;
        const int x0 = int(std::ceil(xlo)), x1 = int(std::floor(xhi));
        for (int x = x0; x <= x1; ++x) {
            const size_t i = size_t(y) * size_t(W) + size_t(x);
            // The nearest occluder here hides what lies beyond its far side.
            dep[i] = opa[i] == 0.0f ? depth : std::min(dep[i], depth);
            covered_ += opa[i] == 0.0f;
            opa[i] = 1.0f;
            any = true;
        }
    }
    return any;
}

bool OcclusionMap::addBox(const dvec3 corners[8]) {
    const dvec3 centre = (corners[0] + corners[7]) * 0.5;
    // Front faces: the eye (the origin) on the outer side of the face's plane.
    bool front[6];
    int nFront = 0;
    double wMax = 0.0;
    for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
            int f[4];
            faceCorners(a, s, f);
            dvec3 nrm = glm::cross(corners[f[1]] - corners[f[0]], corners[f[3]] - corners[f[0]]);
            const dvec3 mid = (corners[f[0]] + corners[f[2]]) * 0.5;
            if (glm::dot(nrm, mid - centre) < 0) nrm = -nrm;
            const bool isFront = glm::dot(nrm, mid) < 0;
            front[2 * a + s] = isFront;
            if (!isFront) continue;
            ++nFront;
            for (int k : f) wMax = std::max(wMax, (viewProj_ * dvec4(corners[k], 1.0)).w);
        }
    if (nFront == 0) return false;  // the eye inside (or a degenerate box)
    const float depth = farDepth(wMax);
    // Wholly beyond the near plane: the front faces cover the outline of the box, one convex polygon.
    bool clipped = false;
    for (int k = 0; k < 8; ++k) clipped |= near_.distance(corners[k]) < 0;
    if (!clipped) {
        hull_.clear();
        poly_.clear();
        for (int k = 0; k < 8; ++k) {
            const dvec4 c = viewProj_ * dvec4(corners[k], 1.0);
            if (!(c.w > 0.0)) return false;
            poly_.push_back({(c.x / c.w * 0.5 + 0.5) * opt_.width, (c.y / c.w * 0.5 + 0.5) * opt_.height});
        }
        // Convex hull (monotone chain).
        std::sort(poly_.begin(), poly_.end(),
                  [](const Pt& p, const Pt& q) { return p.x < q.x || (p.x == q.x && p.y < q.y); });
        hull_.resize(16);
        size_t k = 0;
        for (size_t i = 0; i < poly_.size(); ++i) {
            while (k >= 2 && cross(hull_[k - 1].x - hull_[k - 2].x, hull_[k - 1].y - hull_[k - 2].y,
                                   poly_[i].x - hull_[k - 2].x, poly_[i].y - hull_[k - 2].y) <= 0)
                --k;
            hull_[k++] = poly_[i];
        }
        for (size_t i = poly_.size() - 1, t = k + 1; i-- > 0;) {
            while (k >= t && cross(hull_[k - 1].x - hull_[k - 2].x, hull_[k - 1].y - hull_[k - 2].y,
                                   poly_[i].x - hull_[k - 2].x, poly_[i].y - hull_[k - 2].y) <= 0)
                --k;
            hull_[k++] = poly_[i];
        }
        hull_.resize(k - 1);
        return rasterize(hull_, depth);
    }
    // Cut by the near plane: the GPU clips the faces, and the inside of the box may show through the cut.
    // Each front face on its own (pixels along their shared edges are lost: conservative).
    bool any = false;
    for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
            if (!front[2 * a + s]) continue;
            int f[4];
            faceCorners(a, s, f);
            const dvec3 q[4] = {corners[f[0]], corners[f[1]], corners[f[2]], corners[f[3]]};
            if (project(q, 4, poly_)) any |= rasterize(poly_, depth);
        }
    return any;
}

bool OcclusionMap::addPolygon(const dvec3* v, size_t count) {
    if (count < 3 || count > 30) return false;
    double wMax = 0.0;
    for (size_t k = 0; k < count; ++k) wMax = std::max(wMax, (viewProj_ * dvec4(v[k], 1.0)).w);
    if (!project(v, count, poly_)) return false;
    return rasterize(poly_, farDepth(wMax));
}

void OcclusionMap::finish() {
    // Uncovered pixels hold depth 0: the max pyramid holds covered pixels' depths only.
    for (size_t l = 1; l < opacity_.size(); ++l) {
        const int w = w_[l], h = h_[l], pw = w_[l - 1], ph = h_[l - 1];
        const int sx = pw > w ? 2 : 1, sy = ph > h ? 2 : 1;
        const float scale = 1.0f / float(sx * sy);
        const float* po = opacity_[l - 1].data();
        const float* pd = depth_[l - 1].data();
        float* o = opacity_[l].data();
        float* d = depth_[l].data();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float so = 0.0f, md = 0.0f;
                for (int j = 0; j < sy; ++j)
                    for (int i = 0; i < sx; ++i) {
                        const size_t c = size_t(y * sy + j) * size_t(pw) + size_t(x * sx + i);
                        so += po[c];
                        md = std::max(md, pd[c]);
                    }
                o[size_t(y * w + x)] = so * scale;
                d[size_t(y * w + x)] = md;
            }
    }
}

bool OcclusionMap::covered(int level, int x0, int y0, int x1, int y1, float zmin) const {
    const size_t l = size_t(level);
    const int sx = opt_.width / w_[l], sy = opt_.height / h_[l];  // level-0 pixels per pixel here
    const float* o = opacity_[l].data();
    const float* d = depth_[l].data();
    for (int py = y0 / sy; py <= y1 / sy; ++py)
        for (int px = x0 / sx; px <= x1 / sx; ++px) {
            const size_t i = size_t(py * w_[l] + px);
            if (o[i] >= opt_.opacity && d[i] < zmin) continue;
            if (o[i] == 0.0f || level == 0) return false;
            // Partly covered, or covered but partly nearer: the pixel's part of the rectangle, one level down.
            if (!covered(level - 1, std::max(x0, px * sx), std::max(y0, py * sy), std::min(x1, px * sx + sx - 1),
                         std::min(y1, py * sy + sy - 1), zmin))
                return false;
        }
    return true;
}

OcclusionMap::Result OcclusionMap::test(const dvec3& lo, const dvec3& hi) const {
    dvec3 c[8];
    for (int k = 0; k < 8; ++k) c[k] = dvec3((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    return test(c);
}

OcclusionMap::Result OcclusionMap::test(const dvec3 corners[8]) const {
    if (covered_ == 0) return Result::Visible;
    double xlo = 1e300, ylo = 1e300, xhi = -1e300, yhi = -1e300, zmin = 1e300;
    for (int k = 0; k < 8; ++k) {
        const dvec3& p = corners[k];
        // A corner nearer than the near plane: the rectangle is unbounded; boxes inside may still be tested.
        if (near_.distance(p) < 0) return Result::NotOccluded;
        const dvec4 c = viewProj_ * dvec4(p, 1.0);
        if (!(c.w > 0.0)) return Result::NotOccluded;
        const double x = (c.x / c.w * 0.5 + 0.5) * opt_.width, y = (c.y / c.w * 0.5 + 0.5) * opt_.height;
        xlo = std::min(xlo, x);
        xhi = std::max(xhi, x);
        ylo = std::min(ylo, y);
        yhi = std::max(yhi, y);
        zmin = std::min(zmin, c.w);
    }
    xlo -= opt_.marginX;
    xhi += opt_.marginX;
    ylo -= opt_.marginY;
    yhi += opt_.marginY;
    const int W = opt_.width, H = opt_.height;
    // Off the map is off the screen: only the part on it can be seen.
    if (!(xhi > 0.0 && yhi > 0.0 && xlo < W && ylo < H)) return Result::NotOccluded;
    const int x0 = std::max(0, int(std::floor(xlo))), x1 = std::min(W - 1, int(std::ceil(xhi)) - 1);
    const int y0 = std::max(0, int(std::floor(ylo))), y1 = std::min(H - 1, int(std::ceil(yhi)) - 1);
    // The level where the rectangle spans at most 2 x 2 pixels.
    int level = 0;
    while (level + 1 < levels()) {
        const int sx = W / w_[size_t(level)], sy = H / h_[size_t(level)];
        if (x1 / sx - x0 / sx <= 1 && y1 / sy - y0 / sy <= 1) break;
        ++level;
    }
    const int sx = W / w_[size_t(level)], sy = H / h_[size_t(level)];
    bool anyCover = false;
    for (int py = y0 / sy; py <= y1 / sy; ++py)
        for (int px = x0 / sx; px <= x1 / sx; ++px) anyCover |= opacity(level, px, py) > 0.0f;
    if (!anyCover) return Result::Visible;
    // Nearest depth rounded down to float: beyond the estimate means beyond it in double too.
    float z = float(zmin);
    if (double(z) > zmin) z = std::nextafter(z, -kInfF);
    return covered(level, x0, y0, x1, y1, z) ? Result::Occluded : Result::NotOccluded;
}

}  // namespace sg
