// LodChooser: which children of an LOD entry show this frame, and with what fade: the one place the LOD rules
// live (ranges by distance or by pixel size, the LOD scale, hysteresis, fade bands, the budget's plan, the
// finest child for queries that ask for it, a paged node's detail), so that the cull's walk and its fast path,
// the budget's replay and planner, and the intersection traversal (a pick sees the level that is drawn) agree.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "sg/core/Camera.h"
#include "sg/scene/ImageFrame.h"

#include <algorithm>
#include <cmath>

namespace sg {

class LodChooser {
public:
    static constexpr uint8_t kNone = 0xff;  // no child (LodHistory::kNone)
    static constexpr int kUnplanned = -2;   // Known::planned: the budget did not plan this entry

    // The frame's rules, the same for every entry.
    struct Rules {
        // The view's pixels, for pixel-size LODs. Without one a pixel-size LOD (or paged node) shows its finest
        // child (its detail): a query with no view has no pixels to measure.
        const Camera* camera = nullptr;
        double lodScale = 1.0;    // distances times this, pixel sizes divided by it (CullSettings::lodScale)
        double hysteresis = 0.0;  // above 0: an entry's last child stays within its range widened by this share
        bool fade = false;        // an LOD's fade band (LOD::setTransition) dissolves children across range ends
        bool finest = false;      // every LOD shows its most detailed child (LodChoice::Highest)
    };
    // What the caller knows of one entry beyond its ranges.
    struct Known {
        uint8_t last = kNone;      // the child it showed last frame (hysteresis); kNone: none, or not tracked
        int planned = kUnplanned;  // the budget's child (-1: none); kUnplanned: not planned
    };
    // A child to show: its entry in the image, its number among the LOD's children, and its dissolve (DrawList::fades:
    // 1 none, > 0 keeps pattern values below it, < 0 keeps those at or above 1 + it) when `setsFade`; otherwise
    // it shows as its LOD does.
    struct Shown {
        uint32_t entry, child;
        float fade;
        bool setsFade;
    };

    LodChooser() = default;
    explicit LodChooser(const Rules& r) : rules_(r), special_(r.finest || !r.camera || r.hysteresis > 0.0) {}
    const Rules& rules() const { return rules_; }

    // The value an LOD's ranges are compared with: the eye's distance to its centre times the LOD scale, or its
    // bound's projected diameter in pixels divided by it (pixel-size mode; needs rules().camera). `lod` is entry
    // i's (an LOD's or a PagedLOD's centre and mode), entry i its bound.
    double value(const ImageFrame& f, const FlatImage::Lod& lod, uint32_t i) const {
        const double dist = f.distance(lod.cx, lod.cy, lod.cz);
        if (lod.mode == FlatImage::kScreenError)  // pixels per unit at the sphere: 1 pixel inside it
            return rules_.camera->pixelSize(lod.fade * f.scale, std::max(dist - lod.reach * f.scale, 0.0)) /
                   rules_.lodScale;
        if (lod.mode != uint8_t(LOD::Mode::PixelSize)) return dist * rules_.lodScale;
        return rules_.camera->pixelSize(2.0 * f.img->r[i] * f.scale, dist) / rules_.lodScale;
    }
    double value(const ImageFrame& f, uint32_t i) const { return value(f, lod(*f.img, i), i); }

    // Shows LOD entry i's children for this frame: show(const Shown&) for each, in child order. Returns the first
    // child shown (children past 253 as 254), kNone when none: what LodHistory records. The rules in order: the
    // budget's plan; the finest child; the fade band; hysteresis (with a last child known); the plain ranges.
    // Inlined into the cull's fast path, where a call per LOD showed in the cull's instruction count
    // (docs/benchmarks.md); the rarer rules stay calls.
    template <class Show>
    [[gnu::always_inline]] uint8_t choose(const ImageFrame& f, uint32_t i, const Known& k, Show&& show) const {
        const FlatImage& img = *f.img;
        const FlatImage::Lod& l = lod(img, i);
        if (k.planned != kUnplanned) return k.planned < 0 ? kNone : only(img, i, uint32_t(k.planned), show);
        if (special_) {
            if (rules_.finest || (!rules_.camera && l.mode == uint8_t(LOD::Mode::PixelSize)))
                return only(img, i, uint32_t(finestChild(img, i)), show);
            if (k.last != kNone && !(rules_.fade && l.fade > 0.0f)) return kept(f, i, l, k.last, show);
        }
        const double v = value(f, l, i);
        if (rules_.fade && l.fade > 0.0f) return faded(img, i, &img.ranges[l.firstRange], v, l.fade, show);
        return ranged(img, i, &img.ranges[l.firstRange], v, show);
    }

    // Whether a PagedLOD entry's detail is wanted: by command always, by range when the range holds its value
    // (a detail finest rules always want).
    bool detailWanted(const ImageFrame& f, uint32_t i) const {
        const FlatImage::Paged& p = f.img->paged[f.img->aux[i]];
        if (static_cast<const PagedLOD*>(p.node)->trigger() != PagedLOD::Trigger::Range) return true;
        if (rules_.finest || (!rules_.camera && p.lod.mode != uint8_t(LOD::Mode::Distance))) return true;
        const double v = value(f, p.lod, i);
        return v >= p.min && v < p.max;
    }

    // The first and last children the ranges show for LOD entry i at LOD scale `scale` (-1, -1: none), with the
    // fade band when `band` (a child is drawn where it fades in or out too, as with the fade rule).
    void shownAt(const ImageFrame& f, uint32_t i, double scale, bool band, int& first, int& last) const {
        const FlatImage::Lod& l = lod(*f.img, i);
        const double v = LodChooser({rules_.camera, scale}).value(f, l, i);
        const FlatImage::Range* rg = &f.img->ranges[l.firstRange];
        const double h = band ? 0.5 * double(l.fade) : 0.0;
        first = last = -1;
        int c = 0;
        for (uint32_t j = i + 1; j < f.img->end[i]; j = f.img->end[j], ++c)
            if (v >= rg[c].min - h && v < rg[c].max + h) {
                if (first < 0) first = c;
                last = c;
            }
    }

    // The most detailed child of LOD entry i: the nearest range (distance), the largest pixel size (pixel size).
    static int finestChild(const FlatImage& img, uint32_t i) {
        const FlatImage::Lod& l = lod(img, i);
        const bool pixel = l.mode == uint8_t(LOD::Mode::PixelSize);
        const FlatImage::Range* rg = &img.ranges[l.firstRange];
        int best = 0, c = 0;
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++c)
            if (pixel ? rg[c].max > rg[best].max : rg[c].min < rg[best].min) best = c;
        return best;
    }

    static const FlatImage::Lod& lod(const FlatImage& img, uint32_t i) { return img.lods[img.aux[i]]; }
    static uint8_t child(uint32_t c) { return uint8_t(c < 254 ? c : 254); }

private:
    // The plain ranges: every child whose range holds the value.
    template <class Show>
    static uint8_t ranged(const FlatImage& img, uint32_t i, const FlatImage::Range* rg, double v, Show& show) {
        uint8_t first = kNone;
        uint32_t c = 0;
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++c) {
            if (!(v >= rg[c].min && v < rg[c].max)) continue;
            if (first == kNone) first = child(c);
            show(Shown{j, c, 1.0f, false});
        }
        return first;
    }

    // Hysteresis: the last child stays while the value is within its range widened by rules().hysteresis at both
    // ends; else the plain ranges decide.
    template <class Show>
    [[gnu::noinline]] uint8_t kept(const ImageFrame& f, uint32_t i, const FlatImage::Lod& l, uint8_t last,
                                   Show& show) const {
        const FlatImage& img = *f.img;
        const double v = value(f, l, i), h = rules_.hysteresis;
        const FlatImage::Range* rg = &img.ranges[l.firstRange];
        if (!(h > 0.0 && v >= rg[last].min * (1.0 - h) && v < rg[last].max * (1.0 + h)))
            return ranged(img, i, rg, v, show);
        return only(img, i, last, show);
    }

    template <class Show>
    [[gnu::noinline]] static uint8_t only(const FlatImage& img, uint32_t i, uint32_t wanted, Show& show) {
        uint32_t c = 0;
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++c)
            if (c == wanted) {
                show(Shown{j, c, 1.0f, false});
                return child(c);
            }
        return kNone;
    }

    // A child is drawn over its range widened by half the band at each end; within the band it covers the share
    // of pixels that the position in the band gives. Where two children meet, one keeps the pixels whose pattern
    // value is below its share and the other those at or above it: together exactly every pixel.
    template <class Show>
    [[gnu::noinline]] static uint8_t faded(const FlatImage& img, uint32_t i, const FlatImage::Range* rg, double v,
                                           float width, Show& show) {
        const double w = width, h = 0.5 * w;
        // Shares in steps of 1/4096: exact in float, so complementary shares add up to exactly 1 on the GPU.
        auto share = [](double x) { return float(std::round(std::clamp(x, 0.0, 1.0) * 4096.0) / 4096.0); };
        uint8_t first = kNone;
        uint32_t c = 0;
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++rg, ++c) {
            if (v < rg->min - h || v >= rg->max + h) continue;
            const float in = rg->min > 0.0f ? share((v - (rg->min - h)) / w) : 1.0f;  // nothing below 0 to fade from
            const float out = share((rg->max + h - v) / w);
            // Fading out: keep pattern < out (> 0); fading in: keep pattern >= 1 - in (< 0).
            const float fade = (in >= 1.0f && out >= 1.0f) ? 1.0f : (in < out ? -in : out);
            if (fade == 0.0f) continue;
            if (first == kNone) first = child(c);
            show(Shown{j, c, fade, true});
        }
        return first;
    }

    Rules rules_;
    bool special_ = false;  // rules beyond the ranges and the fade: finest, hysteresis, no camera
};

}  // namespace sg
