// Ear clipping on a doubly linked ring (the scheme of Mapbox's earcut): holes are joined to the outer ring by
// a bridge to a visible vertex; ears are cut while any remain; then collinear and repeated points are dropped,
// small local self-intersections cut off, and finally the ring is split along a valid diagonal and each half
// clipped on its own, so that a polygon is never left half done.
#include "map/data/Triangulate.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace sg {
namespace {

struct Vertex {
    uint32_t i;  // index into the polygon's points
    double x, y;
    Vertex* prev = nullptr;
    Vertex* next = nullptr;
    int32_t z = -1;           // position on the Z-order curve (-1: not yet computed)
    Vertex* prevZ = nullptr;  // the ring's vertices sorted by z, for the ear test's neighbour search
    Vertex* nextZ = nullptr;
    bool steiner = false;
};

// Twice the signed area of (p, q, r), negative when they turn counter-clockwise (earcut's sign).
double area(const Vertex* p, const Vertex* q, const Vertex* r) {
    return (q->y - p->y) * (r->x - q->x) - (q->x - p->x) * (r->y - q->y);
}
bool equals(const Vertex* a, const Vertex* b) { return a->x == b->x && a->y == b->y; }
// q lies on the line through p and r up to the rounding of coordinates that were exactly collinear on the
// source's integer grid before its transform (a spike going back along itself, a straight run): |sin| of the
// turn below 1e-9. Such a point adds no area (at most 1e-9 of its two edges' parallelogram) and is dropped.
bool collinear(const Vertex* p, const Vertex* q, const Vertex* r) {
    const double a = area(p, q, r);
    if (a == 0) return true;
    const double l1 = std::hypot(q->x - p->x, q->y - p->y), l2 = std::hypot(r->x - q->x, r->y - q->y);
    return std::abs(a) <= 1e-9 * l1 * l2;
}
int sign(double v) { return (v > 0) - (v < 0); }

bool pointInTriangle(double ax, double ay, double bx, double by, double cx, double cy, double px, double py) {
    return (cx - px) * (ay - py) >= (ax - px) * (cy - py) && (ax - px) * (by - py) >= (bx - px) * (ay - py) &&
           (bx - px) * (cy - py) >= (cx - px) * (by - py);
}
bool onSegment(const Vertex* p, const Vertex* q, const Vertex* r) {
    return q->x <= std::max(p->x, r->x) && q->x >= std::min(p->x, r->x) && q->y <= std::max(p->y, r->y) &&
           q->y >= std::min(p->y, r->y);
}
bool intersects(const Vertex* p1, const Vertex* q1, const Vertex* p2, const Vertex* q2) {
    const int o1 = sign(area(p1, q1, p2)), o2 = sign(area(p1, q1, q2));
    const int o3 = sign(area(p2, q2, p1)), o4 = sign(area(p2, q2, q1));
    if (o1 != o2 && o3 != o4) return true;
    if (o1 == 0 && onSegment(p1, p2, q1)) return true;
    if (o2 == 0 && onSegment(p1, q2, q1)) return true;
    if (o3 == 0 && onSegment(p2, p1, q2)) return true;
    if (o4 == 0 && onSegment(p2, q1, q2)) return true;
    return false;
}

class EarClipper {
public:
    explicit EarClipper(std::vector<uint32_t>& out) : tri_(out) {}

    void run(const GeoPolygon& poly) {
        // Large rings look for points inside a candidate ear along a Z-order curve instead of around the ring.
        size_t n = poly.outer.size();
        for (const auto& h : poly.holes) n += h.size();
        if (n > 80) {
            glm::dvec2 lo = poly.outer[0], hi = lo;
            auto grow = [&](const GeoRing& r) {
                for (const auto& p : r) lo = glm::min(lo, p), hi = glm::max(hi, p);
            };
            grow(poly.outer);
            for (const auto& h : poly.holes) grow(h);
            const double size = std::max(hi.x - lo.x, hi.y - lo.y);
            if (size > 0.0) {
                minX_ = lo.x, minY_ = lo.y;
                invSize_ = 32767.0 / size;
            }
        }
        uint32_t base = 0;
        Vertex* outer = filter(ring(poly.outer, base, true));
        base += uint32_t(poly.outer.size());
        if (!outer || outer->next == outer->prev) return;
        std::vector<Vertex*> holes;
        for (const GeoRing& h : poly.holes) {
            Vertex* list = filter(ring(h, base, false));
            base += uint32_t(h.size());
            if (!list) continue;
            if (list == list->next) list->steiner = true;
            holes.push_back(leftmost(list));
        }
        std::sort(holes.begin(), holes.end(),
                  [](const Vertex* a, const Vertex* b) { return a->x != b->x ? a->x < b->x : a->y < b->y; });
        for (Vertex* h : holes) outer = eliminateHole(h, outer);
        clip(outer, 0);
    }

private:
    std::vector<uint32_t>& tri_;
    double minX_ = 0.0, minY_ = 0.0, invSize_ = 0.0;  // invSize_ 0: no Z-order search

    int32_t zOrder(double px, double py) const {
        auto spread = [](uint32_t v) {
            v = (v | (v << 8)) & 0x00FF00FFu;
            v = (v | (v << 4)) & 0x0F0F0F0Fu;
            v = (v | (v << 2)) & 0x33333333u;
            return (v | (v << 1)) & 0x55555555u;
        };
        const auto cell = [](double v) { return uint32_t(std::clamp(v, 0.0, 32767.0)); };
        return int32_t(spread(cell((px - minX_) * invSize_)) | (spread(cell((py - minY_) * invSize_)) << 1));
    }

    // Gives every vertex of the ring its z and links them in z order (merge sort on the list).
    void indexCurve(Vertex* start) const {
        Vertex* p = start;
        do {
            if (p->z < 0) p->z = zOrder(p->x, p->y);
            p->prevZ = p->prev;
            p->nextZ = p->next;
            p = p->next;
        } while (p != start);
        p->prevZ->nextZ = nullptr;
        p->prevZ = nullptr;
        Vertex* list = p;
        int merges;
        size_t inSize = 1;
        do {
            Vertex* q = list;
            list = nullptr;
            Vertex* tail = nullptr;
            merges = 0;
            while (q) {
                ++merges;
                Vertex* r = q;
                size_t qSize = 0;
                for (size_t i = 0; i < inSize && r; ++i, r = r->nextZ) ++qSize;
                size_t rSize = inSize;
                while (qSize > 0 || (rSize > 0 && r)) {
                    Vertex* e;
                    if (qSize != 0 && (rSize == 0 || !r || q->z <= r->z)) {
                        e = q, q = q->nextZ, --qSize;
                    } else {
                        e = r, r = r->nextZ, --rSize;
                    }
                    if (tail)
                        tail->nextZ = e;
                    else
                        list = e;
                    e->prevZ = tail;
                    tail = e;
                }
                q = r;
            }
            tail->nextZ = nullptr;
            inSize *= 2;
        } while (merges > 1);
    }
    std::vector<std::unique_ptr<Vertex[]>> blocks_;
    std::vector<std::unique_ptr<Vertex>> extra_;

    Vertex* make(uint32_t i, double x, double y) {
        extra_.push_back(std::make_unique<Vertex>(Vertex{i, x, y}));
        return extra_.back().get();
    }
    static Vertex* insert(Vertex* v, Vertex* last) {
        if (!last) {
            v->prev = v->next = v;
        } else {
            v->next = last->next;
            v->prev = last;
            last->next->prev = v;
            last->next = v;
        }
        return v;
    }
    static void remove(Vertex* v) {
        v->next->prev = v->prev;
        v->prev->next = v->next;
        if (v->prevZ) v->prevZ->nextZ = v->nextZ;
        if (v->nextZ) v->nextZ->prevZ = v->prevZ;
    }

    // The ring as a linked list, counter-clockwise for the outer ring and clockwise for a hole.
    Vertex* ring(const GeoRing& r, uint32_t base, bool outer) {
        const size_t n = r.size();
        if (n == 0) return nullptr;
        blocks_.push_back(std::make_unique<Vertex[]>(n));
        Vertex* vs = blocks_.back().get();
        const bool ccw = ringArea(r) > 0.0;
        Vertex* last = nullptr;
        for (size_t k = 0; k < n; ++k) {
            const size_t j = ccw == outer ? k : n - 1 - k;
            vs[k] = Vertex{base + uint32_t(j), r[j].x, r[j].y};
            last = insert(&vs[k], last);
        }
        if (last && equals(last, last->next)) {
            Vertex* nx = last->next;
            remove(last);
            last = nx == last ? nullptr : nx;
        }
        return last;
    }

    // Drops repeated points and collinear middles between start and end. A middle point is cut off as a
    // (flat) ear rather than dropped: the caller may move the points afterwards (a map projection bends
    // straight runs of longitude and latitude), and the triangles must still cover the ring's area exactly.
    Vertex* filter(Vertex* start, Vertex* end = nullptr) {
        if (!start) return start;
        if (!end) end = start;
        Vertex* p = start;
        bool again;
        do {
            again = false;
            if (!p->steiner && (equals(p, p->next) || collinear(p->prev, p, p->next))) {
                if (!equals(p, p->next) && !equals(p, p->prev) && !equals(p->prev, p->next)) emit(p->prev, p, p->next);
                remove(p);
                p = end = p->prev;
                if (p == p->next) break;
                again = true;
            } else {
                p = p->next;
            }
        } while (again || p != end);
        return end;
    }

    void emit(const Vertex* a, const Vertex* b, const Vertex* c) {
        tri_.push_back(a->i);
        tri_.push_back(b->i);
        tri_.push_back(c->i);
    }

    void clip(Vertex* ear, int pass) {
        if (!ear) return;
        if (pass == 0 && invSize_ > 0.0) indexCurve(ear);
        Vertex* stop = ear;
        while (ear->prev != ear->next) {
            Vertex* prev = ear->prev;
            Vertex* next = ear->next;
            if (invSize_ > 0.0 ? isEarHashed(ear) : isEar(ear)) {
                emit(prev, ear, next);
                remove(ear);
                ear = next->next;
                stop = next->next;
                continue;
            }
            ear = next;
            if (ear == stop) {
                if (pass == 0) {
                    clip(filter(ear), 1);
                } else if (pass == 1) {
                    ear = cureLocalIntersections(filter(ear));
                    clip(ear, 2);
                } else {
                    split(ear);
                }
                break;
            }
        }
    }

    static bool isEar(const Vertex* ear) {
        const Vertex *a = ear->prev, *b = ear, *c = ear->next;
        if (area(a, b, c) >= 0) return false;  // reflex
        const double x0 = std::min({a->x, b->x, c->x}), y0 = std::min({a->y, b->y, c->y});
        const double x1 = std::max({a->x, b->x, c->x}), y1 = std::max({a->y, b->y, c->y});
        for (const Vertex* p = c->next; p != a; p = p->next) {
            if (p->x >= x0 && p->x <= x1 && p->y >= y0 && p->y <= y1 &&
                pointInTriangle(a->x, a->y, b->x, b->y, c->x, c->y, p->x, p->y) && !(equals(p, a) || equals(p, c)) &&
                area(p->prev, p, p->next) >= 0)
                return false;
        }
        return true;
    }

    // A point of the ring inside the triangle (a, b, c) that blocks it as an ear.
    static bool blocks(const Vertex* p, const Vertex* a, const Vertex* b, const Vertex* c, double x0, double y0,
                       double x1, double y1) {
        return p->x >= x0 && p->x <= x1 && p->y >= y0 && p->y <= y1 && p != a && p != c && !equals(p, a) &&
               !equals(p, c) && pointInTriangle(a->x, a->y, b->x, b->y, c->x, c->y, p->x, p->y) &&
               area(p->prev, p, p->next) >= 0;
    }

    // isEar, visiting only the vertices whose z lies in the triangle's box's range, nearest first both ways.
    bool isEarHashed(const Vertex* ear) const {
        const Vertex *a = ear->prev, *b = ear, *c = ear->next;
        if (area(a, b, c) >= 0) return false;
        const double x0 = std::min({a->x, b->x, c->x}), y0 = std::min({a->y, b->y, c->y});
        const double x1 = std::max({a->x, b->x, c->x}), y1 = std::max({a->y, b->y, c->y});
        const int32_t minZ = zOrder(x0, y0), maxZ = zOrder(x1, y1);
        const Vertex* p = ear->prevZ;
        const Vertex* n = ear->nextZ;
        while (p && p->z >= minZ && n && n->z <= maxZ) {
            if (blocks(p, a, b, c, x0, y0, x1, y1) || blocks(n, a, b, c, x0, y0, x1, y1)) return false;
            p = p->prevZ;
            n = n->nextZ;
        }
        for (; p && p->z >= minZ; p = p->prevZ)
            if (blocks(p, a, b, c, x0, y0, x1, y1)) return false;
        for (; n && n->z <= maxZ; n = n->nextZ)
            if (blocks(n, a, b, c, x0, y0, x1, y1)) return false;
        return true;
    }

    Vertex* cureLocalIntersections(Vertex* start) {
        Vertex* p = start;
        do {
            Vertex* a = p->prev;
            Vertex* b = p->next->next;
            if (!equals(a, b) && intersects(a, p, p->next, b) && locallyInside(a, b) && locallyInside(b, a)) {
                emit(a, p, b);
                remove(p);
                remove(p->next);
                p = start = b;
            }
            p = p->next;
        } while (p != start);
        return filter(p);
    }

    void split(Vertex* start) {
        Vertex* a = start;
        do {
            for (Vertex* b = a->next->next; b != a->prev; b = b->next) {
                if (a->i != b->i && isValidDiagonal(a, b)) {
                    Vertex* c = splitPolygon(a, b);
                    a = filter(a, a->next);
                    c = filter(c, c->next);
                    clip(a, 0);
                    clip(c, 0);
                    return;
                }
            }
            a = a->next;
        } while (a != start);
    }

    static bool locallyInside(const Vertex* a, const Vertex* b) {
        return area(a->prev, a, a->next) < 0 ? area(a, b, a->next) >= 0 && area(a, a->prev, b) >= 0
                                             : area(a, b, a->prev) < 0 || area(a, a->next, b) < 0;
    }
    static bool middleInside(const Vertex* a, const Vertex* b) {
        const Vertex* p = a;
        bool inside = false;
        const double px = (a->x + b->x) / 2, py = (a->y + b->y) / 2;
        do {
            if (((p->y > py) != (p->next->y > py)) && p->next->y != p->y &&
                (px < (p->next->x - p->x) * (py - p->y) / (p->next->y - p->y) + p->x))
                inside = !inside;
            p = p->next;
        } while (p != a);
        return inside;
    }
    static bool intersectsPolygon(const Vertex* a, const Vertex* b) {
        const Vertex* p = a;
        do {
            if (p->i != a->i && p->next->i != a->i && p->i != b->i && p->next->i != b->i &&
                intersects(p, p->next, a, b))
                return true;
            p = p->next;
        } while (p != a);
        return false;
    }
    static bool isValidDiagonal(const Vertex* a, const Vertex* b) {
        return a->next->i != b->i && a->prev->i != b->i && !intersectsPolygon(a, b) &&
               ((locallyInside(a, b) && locallyInside(b, a) && middleInside(a, b) &&
                 (area(a->prev, a, b->prev) != 0 || area(a, b->prev, b) != 0)) ||
                (equals(a, b) && area(a->prev, a, a->next) > 0 && area(b->prev, b, b->next) > 0));
    }

    // Links a and b by a two-way edge; returns the copy of b on the new second ring.
    Vertex* splitPolygon(Vertex* a, Vertex* b) {
        Vertex* a2 = make(a->i, a->x, a->y);
        Vertex* b2 = make(b->i, b->x, b->y);
        Vertex* an = a->next;
        Vertex* bp = b->prev;
        a->next = b;
        b->prev = a;
        a2->next = an;
        an->prev = a2;
        b2->next = a2;
        a2->prev = b2;
        bp->next = b2;
        b2->prev = bp;
        return b2;
    }

    static Vertex* leftmost(Vertex* start) {
        Vertex *p = start, *l = start;
        do {
            if (p->x < l->x || (p->x == l->x && p->y < l->y)) l = p;
            p = p->next;
        } while (p != start);
        return l;
    }

    static bool sectorContainsSector(const Vertex* m, const Vertex* p) {
        return area(m->prev, m, p->prev) < 0 && area(p->next, m, m->next) < 0;
    }

    // The outer vertex the hole's leftmost point connects to: the nearest edge hit by a ray to the left,
    // then, among reflex vertices in the triangle it spans, the one at the smallest angle.
    static Vertex* findHoleBridge(Vertex* hole, Vertex* outer) {
        Vertex* p = outer;
        const double hx = hole->x, hy = hole->y;
        double qx = -std::numeric_limits<double>::infinity();
        Vertex* m = nullptr;
        do {
            if (hy <= p->y && hy >= p->next->y && p->next->y != p->y) {
                const double x = p->x + (hy - p->y) * (p->next->x - p->x) / (p->next->y - p->y);
                if (x <= hx && x > qx) {
                    qx = x;
                    m = p->x < p->next->x ? p : p->next;
                    if (x == hx) return m;  // the hole touches the outer ring
                }
            }
            p = p->next;
        } while (p != outer);
        if (!m) return nullptr;
        const Vertex* stop = m;
        const double mx = m->x, my = m->y;
        double tanMin = std::numeric_limits<double>::infinity();
        p = m;
        do {
            if (hx >= p->x && p->x >= mx && hx != p->x &&
                pointInTriangle(hy < my ? hx : qx, hy, mx, my, hy < my ? qx : hx, hy, p->x, p->y)) {
                const double tan = std::abs(hy - p->y) / (hx - p->x);
                if (locallyInside(p, hole) &&
                    (tan < tanMin ||
                     (tan == tanMin && (p->x > m->x || (p->x == m->x && sectorContainsSector(m, p)))))) {
                    m = p;
                    tanMin = tan;
                }
            }
            p = p->next;
        } while (p != stop);
        return m;
    }

    Vertex* eliminateHole(Vertex* hole, Vertex* outer) {
        Vertex* bridge = findHoleBridge(hole, outer);
        if (!bridge) return outer;
        Vertex* reverse = splitPolygon(bridge, hole);
        filter(reverse, reverse->next);
        return filter(bridge, bridge->next);
    }
};

double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

struct Crossing {
    double t;  // along the edge
    glm::dvec2 p;
    int id;
};

// The ring's loops, cut at the points where two of its edges cross properly (each inside both edges).
std::vector<GeoRing> splitRing(const GeoRing& r) {
    const size_t n = r.size();
    if (n < 4) return {r};
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = i;
    auto lo = [&](size_t i) { return std::min(r[i].x, r[(i + 1) % n].x); };
    auto hi = [&](size_t i) { return std::max(r[i].x, r[(i + 1) % n].x); };
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return lo(a) < lo(b); });
    std::vector<std::vector<Crossing>> at(n);
    int ids = 0;
    std::vector<size_t> active;
    for (size_t i : order) {
        const double x = lo(i);
        active.erase(std::remove_if(active.begin(), active.end(), [&](size_t j) { return hi(j) < x; }), active.end());
        const glm::dvec2 a = r[i], b = r[(i + 1) % n];
        for (size_t j : active) {
            if (j == (i + 1) % n || i == (j + 1) % n) continue;
            const glm::dvec2 c = r[j], d = r[(j + 1) % n];
            if (std::max(a.y, b.y) < std::min(c.y, d.y) || std::max(c.y, d.y) < std::min(a.y, b.y)) continue;
            const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
            if (!((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) || !((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) continue;
            const double t = o3 / (o3 - o4), u = o1 / (o1 - o2);
            const glm::dvec2 p = a + (b - a) * t;
            at[i].push_back({t, p, ids});
            at[j].push_back({u, p, ids});
            ++ids;
        }
        active.push_back(i);
    }
    if (ids == 0) return {r};
    // The ring with the crossings in place, then loops cut off each time a crossing comes round again.
    std::vector<std::pair<glm::dvec2, int>> stack;
    std::vector<int> seen(size_t(ids), -1);  // position of a crossing's first visit on the stack
    std::vector<GeoRing> loops;
    auto visit = [&](const glm::dvec2& p, int id) {
        if (id >= 0 && seen[size_t(id)] >= 0) {
            const size_t from = size_t(seen[size_t(id)]);
            GeoRing loop;
            for (size_t k = from; k < stack.size(); ++k) {
                loop.push_back(stack[k].first);
                if (stack[k].second >= 0 && k > from) seen[size_t(stack[k].second)] = -1;
            }
            stack.resize(from + 1);
            if (loop.size() >= 3) loops.push_back(std::move(loop));
            return;
        }
        if (id >= 0) seen[size_t(id)] = int(stack.size());
        stack.push_back({p, id});
    };
    for (size_t i = 0; i < n; ++i) {
        visit(r[i], -1);
        std::sort(at[i].begin(), at[i].end(), [](const Crossing& a, const Crossing& b) { return a.t < b.t; });
        for (const Crossing& c : at[i]) visit(c.p, c.id);
    }
    GeoRing rest;
    for (const auto& [p, id] : stack) rest.push_back(p);
    if (rest.size() >= 3) loops.push_back(std::move(rest));
    return loops;
}

}  // namespace

std::vector<GeoPolygon> splitSelfCrossings(const GeoPolygon& polygon) {
    std::vector<GeoRing> outers = splitRing(polygon.outer);
    std::vector<GeoRing> holes;
    bool changed = outers.size() != 1;
    for (const GeoRing& h : polygon.holes) {
        std::vector<GeoRing> parts = splitRing(h);
        changed = changed || parts.size() != 1;
        for (auto& p : parts) holes.push_back(std::move(p));
    }
    if (!changed) return {polygon};
    std::vector<GeoPolygon> out;
    size_t largest = 0;
    for (size_t k = 0; k < outers.size(); ++k) {
        if (std::abs(ringArea(outers[k])) > std::abs(ringArea(outers[largest]))) largest = k;
        out.push_back(GeoPolygon{std::move(outers[k]), {}});
    }
    if (!out.empty()) out[largest].holes = std::move(holes);
    return out;
}

double ringArea(const GeoRing& r) {
    double s = 0.0;
    const size_t n = r.size();
    for (size_t i = 0, j = n - 1; i < n; j = i++) s += (r[j].x - r[i].x) * (r[j].y + r[i].y);
    return s / 2.0;
}

double polygonArea(const GeoPolygon& p) {
    double a = std::abs(ringArea(p.outer));
    for (const auto& h : p.holes) a -= std::abs(ringArea(h));
    return a;
}

std::vector<uint32_t> triangulatePolygon(const GeoPolygon& polygon) {
    std::vector<uint32_t> out;
    EarClipper(out).run(polygon);
    return out;
}

}  // namespace sg
