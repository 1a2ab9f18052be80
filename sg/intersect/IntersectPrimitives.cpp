#include "sg/intersect/internal/IntersectPrimitives.h"

namespace sg {
namespace isect {

dvec3 closestPointOnTriangle(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c) noexcept {
    const dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
    const dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double den = va + vb + vc;
    if (!(den > 0.0)) {  // degenerate (a segment or a point): the nearest of its edges
        dvec3 best = a;
        double bd = kInf;
        for (const auto& e : {std::pair<dvec3, dvec3>{a, b}, {b, c}, {c, a}}) {
            const dvec3 s = e.second - e.first;
            const double l2 = glm::dot(s, s);
            const double f = l2 > 0.0 ? glm::clamp(glm::dot(p - e.first, s) / l2, 0.0, 1.0) : 0.0;
            const dvec3 q = e.first + s * f;
            const double dq = glm::dot(p - q, p - q);
            if (dq < bd) bd = dq, best = q;
        }
        return best;
    }
    return a + ab * (vb / den) + ac * (vc / den);
}

void barycentric(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c, double& u, double& v) noexcept {
    const dvec3 e1 = b - a, e2 = c - a, w = p - a;
    const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const double w1 = glm::dot(w, e1), w2 = glm::dot(w, e2);
    const double den = d11 * d22 - d12 * d12;
    if (!(den > 0.0)) {
        u = v = 0.0;
        return;
    }
    u = (d22 * w1 - d12 * w2) / den;
    v = (d11 * w2 - d12 * w1) / den;
}

namespace {
// Smallest root of A t^2 + B t + C = 0 in [0, tBest), for a distance that starts outside (C >= 0 up to
// rounding) and a motion that brings it in (A > 0).
bool lowestRoot(double A, double B, double C, double tBest, double& t) noexcept {
    if (!(A > 0.0)) return false;
    const double disc = B * B - 4.0 * A * C;
    if (!(disc >= 0.0)) return false;
    const double s = std::sqrt(disc);
    double t1 = (-B - s) / (2.0 * A);
    const double t2 = (-B + s) / (2.0 * A);
    if (t1 < 0.0) {
        if (t2 < 0.0 || B >= 0.0) return false;  // behind, or rounding while moving away
        t1 = 0.0;
    }
    if (!(t1 < tBest)) return false;
    t = t1;
    return true;
}

bool insideTriangle(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& n) noexcept {
    return glm::dot(glm::cross(b - a, p - a), n) >= 0.0 && glm::dot(glm::cross(c - b, p - b), n) >= 0.0 &&
           glm::dot(glm::cross(a - c, p - c), n) >= 0.0;
}
}  // namespace

bool sweepSphereTriangle(const dvec3& c0, const dvec3& d, double r, const dvec3& a, const dvec3& b, const dvec3& c,
                         double tBest, double& t, dvec3& point, dvec3& normal) noexcept {
    const dvec3 nn = glm::cross(b - a, c - a);
    const double nlen = glm::length(nn);
    const double dd = glm::dot(d, d);
    // Already overlapping: a contact at 0 if the motion goes further in.
    const dvec3 q = closestPointOnTriangle(c0, a, b, c);
    const dvec3 w = c0 - q;
    const double w2 = glm::dot(w, w);
    if (w2 < r * r) {
        dvec3 n;
        if (w2 > 0.0) {
            n = w / std::sqrt(w2);
        } else if (nlen > 0.0) {  // the centre on the triangle: out through the side it comes from
            n = nn / nlen;
            if (glm::dot(n, d) > 0.0) n = -n;
        } else {
            return false;
        }
        if (!(glm::dot(d, n) < -eps::kRounding * std::sqrt(dd))) return false;
        t = 0.0, point = q, normal = n;
        return true;
    }
    if (!(dd > 0.0) || !(tBest > 0.0)) return false;
    bool found = false;
    double best = tBest;
    // The face: the first touch of the plane, if it lands inside the triangle, is the first contact.
    if (nlen > 0.0) {
        const dvec3 n = nn / nlen;
        const double s0 = glm::dot(n, c0 - a), dn = glm::dot(n, d);
        if (std::abs(s0) >= r && s0 * dn < 0.0) {  // outside its slab and moving toward the plane
            const double side = s0 > 0.0 ? 1.0 : -1.0;
            const double tp = (side * r - s0) / dn;
            if (tp >= 0.0 && tp < best) {
                const dvec3 pc = c0 + d * tp - n * (side * r);
                if (insideTriangle(pc, a, b, c, n)) {
                    t = tp, point = pc, normal = n * side;
                    return true;
                }
            }
        }
    }
    // Otherwise the first contact is with a vertex or an edge.
    double tr;
    for (const dvec3* p : {&a, &b, &c}) {
        const dvec3 B = c0 - *p;
        if (lowestRoot(dd, 2.0 * glm::dot(B, d), glm::dot(B, B) - r * r, best, tr)) {
            best = tr, point = *p, found = true;
        }
    }
    const dvec3* ends[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
    for (auto& e : ends) {
        const dvec3& p = *e[0];
        const dvec3 E = *e[1] - p, B = c0 - p;
        const double ee = glm::dot(E, E), de = glm::dot(d, E), be = glm::dot(B, E);
        if (!(ee > 0.0)) continue;
        if (!lowestRoot(ee * dd - de * de, 2.0 * (ee * glm::dot(B, d) - be * de),
                        ee * glm::dot(B, B) - be * be - r * r * ee, best, tr))
            continue;
        const double s = (be + tr * de) / ee;
        if (s < 0.0 || s > 1.0) continue;
        best = tr, point = p + E * s, found = true;
    }
    if (!found) return false;
    t = best;
    const dvec3 toCentre = c0 + d * t - point;
    const double len = glm::length(toCentre);
    normal = len > 0.0 ? toCentre / len : -d / std::sqrt(dd);
    return true;
}

void closestRaySegment(const dvec3& o, const dvec3& d, double tMax, const dvec3& p0, const dvec3& p1, double& t,
                       double& u) noexcept {
    const dvec3 e = p1 - p0, r = o - p0;
    const double a = glm::dot(d, d), ee = glm::dot(e, e), f = glm::dot(e, r), c = glm::dot(d, r);
    auto clampT = [&](double x) { return x < 0.0 ? 0.0 : (x > tMax ? tMax : x); };
    if (!(ee > 0.0)) {  // the segment is a point
        u = 0.0;
        t = clampT(-c / a);
        return;
    }
    const double b = glm::dot(d, e), denom = a * ee - b * b;
    // Not parallel: the lines' closest point on the ray, clamped; parallel: any t (the origin's).
    t = denom > 0.0 ? clampT((b * f - c * ee) / denom) : 0.0;
    u = (b * t + f) / ee;
    // The segment's point clamped to its ends, and the ray's point recomputed for that end.
    if (u < 0.0) {
        u = 0.0;
        t = clampT(-c / a);
    } else if (u > 1.0) {
        u = 1.0;
        t = clampT((b - c) / a);
    }
}

}  // namespace isect
}  // namespace sg
