#include "testbed/Pareto.h"

#include "sg/cull/CullTraversal.h"
#include "sg/gl/OcclusionQueries.h"
#include "sg/io/ImageIO.h"
#include "testbed/Stats.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace pareto {

using namespace sg;

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

CullSettings frustumOnly(CullStrategy s, double smallFeaturePixels = 0.0) {
    CullSettings c;
    c.strategy = s;
    c.smallFeaturePixels = smallFeaturePixels;
    c.occlusion.mode = OcclusionMode::Off;
    return c;
}

// Boxes and an occlusion method every frame (Adaptive could skip frames: that is the default's row).
CullSettings withOcclusion(OcclusionMethod m, double homOpacity) {
    CullSettings c;
    c.occlusion.mode = OcclusionMode::EveryFrame;
    c.occlusion.method = m;
    c.occlusion.homOpacity = homOpacity;
    return c;
}

// Where a draw item stands (its eye-relative translation to the millimetre): the same geometry culled by
// different settings gets the same key even if its float matrix took another path through the cull.
struct Place {
    int64_t x, y, z;
    bool operator==(const Place& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PlaceHash {
    size_t operator()(const Place& p) const {
        return size_t(uint64_t(p.x) * 0x9E3779B97F4A7C15ull ^ uint64_t(p.y) * 0xC2B2AE3D27D4EB4Full ^
                      uint64_t(p.z) * 0x165667B19E3779F9ull);
    }
};
Place placeOf(const DrawItem& it) {
    const glm::vec3 t = it.model[3];
    return {std::llround(double(t.x) * 1000.0), std::llround(double(t.y) * 1000.0), std::llround(double(t.z) * 1000.0)};
}
using Placed = std::unordered_map<Place, std::vector<const Mesh*>, PlaceHash>;
Placed placed(const DrawList& l) {
    Placed p;
    p.reserve(l.items.size());
    for (const DrawItem& it : l.items) p[placeOf(it)].push_back(it.mesh);
    return p;
}
bool holds(const Placed& p, const Place& at, const Mesh* m) {
    auto it = p.find(at);
    return it != p.end() && std::find(it->second.begin(), it->second.end(), m) != it->second.end();
}

// The id render: each reference item unlit in a colour of its own, on its mesh without vertex colours or uvs
// (those would multiply the id colour). Cut-out foliage counts as its whole quad.
class IdRender {
public:
    // visible[i]: item i of `ref` owns at least one pixel.
    std::vector<char> visible(Renderer& r, const DrawList& ref, const Camera& cam) {
        list_.clear();
        list_.items = ref.items;
        while (ids_.size() < list_.items.size()) {
            const uint32_t k = uint32_t(ids_.size()) + 1;
            auto m = make<Material>(
                vec4(float(k & 255) / 255.0f, float((k >> 8) & 255) / 255.0f, float((k >> 16) & 255) / 255.0f, 1.0f));
            m->unlit = true;
            ids_.push_back(m);
        }
        for (size_t i = 0; i < list_.items.size(); ++i) {
            list_.items[i].material = ids_[i].get();
            list_.items[i].mesh = plain(list_.items[i].mesh);
        }
        r.draw(list_, cam, vec4(0, 0, 0, 1));
        const Image img = r.readColor();
        std::vector<char> seen(list_.items.size(), 0);
        for (size_t p = 0; p + 3 < img.rgba.size(); p += 4) {
            const uint32_t k = img.rgba[p] | (img.rgba[p + 1] << 8) | (img.rgba[p + 2] << 16);
            if (k && k <= seen.size()) seen[k - 1] = 1;
        }
        return seen;
    }

private:
    const Mesh* plain(const Mesh* m) {
        if (m->colors().empty() && m->uvs().empty()) return m;
        auto& copy = plain_[m];
        if (!copy) {
            std::vector<uint32_t> idx(m->indexCount());
            for (size_t i = 0; i < idx.size(); ++i) idx[i] = m->index(i);
            copy = make<Mesh>();
            copy->set(m->positions(), m->normals(), std::move(idx));
        }
        return copy.get();
    }
    DrawList list_;
    std::vector<ref_ptr<Material>> ids_;
    std::unordered_map<const Mesh*, ref_ptr<Mesh>> plain_;
};

// Reference-visible items that `got` does not draw, neither as themselves nor as another level (a mesh at
// the same place that the reference does not draw there).
uint64_t wronglyCulled(const DrawList& ref, const std::vector<char>& visible, const Placed& refAt,
                       const DrawList& got) {
    const Placed gotAt = placed(got);
    uint64_t wrong = 0;
    for (size_t i = 0; i < ref.items.size(); ++i) {
        if (!visible[i]) continue;
        const Place at = placeOf(ref.items[i]);
        if (holds(gotAt, at, ref.items[i].mesh)) continue;
        bool otherLevel = false;
        auto it = gotAt.find(at);
        if (it != gotAt.end())
            for (const Mesh* m : it->second) otherLevel = otherLevel || !holds(refAt, at, m);
        wrong += !otherLevel;
    }
    return wrong;
}

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}
}  // namespace

std::vector<Method> methods() {
    using S = CullStrategy;
    using L = sg::LodPolicy;
    return {
        {"none", frustumOnly(S::None), L::Static, true, false, false, false},
        {"center-box", frustumOnly(S::CenterBox), L::Static, false, false, false, false},
        // The PCVR paper's pair: centres against the frustum's box, then clusters of triangles whose screen
        // rectangle is off the viewport dropped (conservative on its own: the error is center-box's).
        {"center-box+screen-rect",
         [] {
             auto c = frustumOnly(S::CenterBox);
             c.screenRect = true;
             return c;
         }(),
         L::Static, false, false, false, false},
        {"aabb+screen-rect",
         [] {
             auto c = frustumOnly(S::Aabb);
             c.screenRect = true;
             return c;
         }(),
         L::Static, true, false, false, false},
        {"sphere", frustumOnly(S::Sphere), L::Static, true, false, false, false},
        {"sphere-sphere", frustumOnly(S::SphereSphere), L::Static, true, false, false, false},
        {"aabb", frustumOnly(S::Aabb), L::Static, true, false, false, false},
        {"aabb+small-feature-1px", frustumOnly(S::Aabb, 1.0), L::Static, false, false, false, false},
        {"aabb+small-feature-2px", frustumOnly(S::Aabb, 2.0), L::Static, false, false, false, false},
        {"aabb+small-feature-4px", frustumOnly(S::Aabb, 4.0), L::Static, false, false, false, false},
        {"occlusion-tree", withOcclusion(OcclusionMethod::Tree, 1.0), L::Static, true, false, false, false},
        {"hom", withOcclusion(OcclusionMethod::Hom, 1.0), L::Static, true, false, false, false},
        {"hom-approx", withOcclusion(OcclusionMethod::Hom, 0.75), L::Static, false, false, false, false},
        // OpenSceneGraph's OcclusionQueryNode: a query per item every frame, whose answer decides the next frame.
        {"gpu-query", frustumOnly(S::Aabb), L::Static, false, false, false, true},
        {"default", CullSettings{}, L::Static, true, true, false, false},
        {"lod-stress", CullSettings{}, L::Stress, true, false, true, false},
        {"lod-budget", CullSettings{}, L::Budget, true, false, true, false},
    };
}

std::vector<Method> selectMethods(const std::vector<Method>& all, const std::string& names) {
    if (names.empty()) return all;
    std::vector<std::string> want;
    std::stringstream ss(names);
    for (std::string n; std::getline(ss, n, ',');) want.push_back(n);
    for (const std::string& n : want) {
        if (std::none_of(all.begin(), all.end(), [&](const Method& m) { return m.name == n; })) {
            std::string valid;
            for (const Method& m : all) valid += (valid.empty() ? "" : ", ") + m.name;
            throw std::invalid_argument("pareto::selectMethods(): no method '" + n + "' (valid: " + valid + ")");
        }
    }
    std::vector<Method> out;
    for (const Method& m : all)
        if (std::find(want.begin(), want.end(), m.name) != want.end()) out.push_back(m);
    return out;
}

std::vector<Row> measure(Renderer& r, const SceneViews& sv, const std::vector<Method>& all, const Options& o) {
    if (!sv.scene || sv.views.empty())
        throw std::invalid_argument("pareto::measure(): scene '" + sv.name + "' has no scene or no views");
    if (all.empty()) throw std::invalid_argument("pareto::measure(): no methods");
    if (o.rounds < 1) throw std::invalid_argument("pareto::measure(): rounds " + std::to_string(o.rounds) + " < 1");
    std::vector<const Method*> use;
    for (const Method& m : all)
        if (!m.needsLods || sv.hasLods) use.push_back(&m);
    const size_t M = use.size(), V = sv.views.size();
    Scene& scene = *sv.scene;
    auto prepare = [&](size_t v) {
        if (sv.prepare) sv.prepare(v);
    };

    // One traversal (or LOD run) per method: the occlusion pass's Adaptive state and the LOD methods' feedback
    // follow the views as they would follow frames.
    std::vector<std::unique_ptr<CullTraversal>> culls(M);
    std::vector<std::unique_ptr<scenes::LodRun>> runs(M);
    std::vector<std::unique_ptr<OcclusionQueries>> queries(M);  // a method's queries answer its own last frame
    for (size_t k = 0; k < M; ++k) {
        if (use[k]->lod == sg::LodPolicy::Static) {
            culls[k] = std::make_unique<CullTraversal>();
            if (use[k]->gpuQueries) queries[k] = std::make_unique<OcclusionQueries>();
        } else
            runs[k] = std::make_unique<scenes::LodRun>(
                r, scenes::LodRun::Settings{use[k]->lod, o.budgetMs, true, use[k]->cull});
    }
    CullSettings ref = frustumOnly(o.strictReference ? CullStrategy::None : CullStrategy::Aabb);
    ref.lodScale = 1e-9;  // every LOD at its finest level
    ref.lodFade = false;
    CullTraversal refCull;
    DrawList refList, list;
    CullStats st;
    IdRender ids;

    // Untimed: every method once at the first view (uploads), and the LOD runs once along the views (stress's
    // scale and the budget's cost model settle).
    prepare(0);
    for (size_t k = 0; k < M; ++k)
        if (culls[k]) {
            culls[k]->cull(scene, sv.views[0], use[k]->cull, list, st);
            if (queries[k]) {
                queries[k]->draw(r, list, sv.views[0]);
                r.finish();
                queries[k]->reset();  // the first timed frame has no frame before it
            } else {
                r.draw(list, sv.views[0]);
            }
        }
    for (size_t k = 0; k < M; ++k)
        if (runs[k])
            for (size_t v = 0; v < V; ++v) {
                prepare(v);
                runs[k]->frame(scene, sv.views[v]);
            }

    struct Acc {
        std::vector<double> cull, frame;
        double objects = 0, triangles = 0, error = 0, queries = 0;
        int viewsWithError = 0;
        uint64_t wrong = 0;
    };
    std::vector<Acc> acc(M);
    for (int round = 0; round < o.rounds; ++round) {
        for (size_t v = 0; v < V; ++v) {
            const Camera& cam = sv.views[v];
            prepare(v);
            Image refImg;
            std::vector<char> visible;
            Placed refAt;
            if (round == 0) {
                refCull.cull(scene, cam, ref, refList, st);
                r.draw(refList, cam);
                refImg = r.readColor();
                visible = ids.visible(r, refList, cam);
                refAt = placed(refList);
            }
            for (size_t j = 0; j < M; ++j) {
                const size_t k = (v + size_t(round) + j) % M;
                const DrawList* drawn = &list;
                CullStats s;
                double cullMs = 0.0, frameMs = 0.0;
                if (runs[k]) {
                    const scenes::LodFrame& f = runs[k]->frame(scene, cam);
                    cullMs = f.cullMs;
                    frameMs = f.frameMs;
                    s = f.stats;
                    drawn = &runs[k]->list();
                } else {
                    const auto t0 = Clock::now();
                    culls[k]->cull(scene, cam, use[k]->cull, list, s);
                    cullMs = msSince(t0);
                    if (queries[k]) {
                        queries[k]->draw(r, list, cam);
                        drawn = &queries[k]->drawn();
                    } else {
                        r.draw(list, cam);
                    }
                    r.finish();
                    frameMs = msSince(t0);
                    if (queries[k]) {  // what was drawn: the cull's items less those the queries hid
                        const OcclusionQueries::Stats& q = queries[k]->lastStats();
                        s.geometries -= q.hidden;
                        s.triangles -= q.hiddenTriangles;
                        if (round == 0) acc[k].queries += q.queries;
                    }
                }
                Acc& a = acc[k];
                a.cull.push_back(cullMs);
                a.frame.push_back(frameMs);
                if (round != 0) continue;
                a.objects += double(s.geometries);
                a.triangles += double(s.triangles);
                const uint64_t d = countDifferingPixels(refImg, r.readColor());
                a.error += double(d);
                a.viewsWithError += d > 0;
                a.wrong += wronglyCulled(refList, visible, refAt, *drawn);
            }
        }
    }

    std::vector<Row> rows(M);
    const double pixels = double(sv.views[0].width()) * double(sv.views[0].height());
    for (size_t k = 0; k < M; ++k) {
        Row& w = rows[k];
        const Acc& a = acc[k];
        w.scene = sv.name;
        w.method = use[k]->name;
        w.conservative = use[k]->conservative;
        w.isDefault = use[k]->isDefault;
        w.views = int(V);
        w.rounds = o.rounds;
        w.width = sv.views[0].width();
        w.height = sv.views[0].height();
        w.cullMs = stats::median(a.cull);
        w.frameMs = stats::median(a.frame);
        w.objects = a.objects / double(V);
        w.triangles = a.triangles / double(V);
        w.errorPixels = a.error / double(V);
        w.errorPercent = 100.0 * w.errorPixels / pixels;
        w.viewsWithError = a.viewsWithError;
        w.wronglyCulledTotal = a.wrong;
        w.wronglyCulled = double(a.wrong) / double(V);
        w.queries = a.queries / double(V);
        w.frames = a.frame;
    }
    for (const Row& none : rows)
        if (none.method == "none")
            for (Row& w : rows) {
                w.cullRatio = none.cullMs > 0 ? w.cullMs / none.cullMs : 0.0;
                w.frameRatio = none.frameMs > 0 ? w.frameMs / none.frameMs : 0.0;
            }
    markFront(rows);
    return rows;
}

std::vector<bool> paretoFront(const std::vector<double>& time, const std::vector<double>& error) {
    if (time.size() != error.size())
        throw std::invalid_argument("pareto::paretoFront(): " + std::to_string(time.size()) + " times but " +
                                    std::to_string(error.size()) + " errors");
    std::vector<bool> on(time.size(), true);
    for (size_t i = 0; i < time.size(); ++i)
        for (size_t j = 0; j < time.size() && on[i]; ++j)
            if (time[j] < time[i] && error[j] <= error[i]) on[i] = false;
    return on;
}

void markFront(std::vector<Row>& rows) {
    std::map<std::string, std::vector<size_t>> byScene;
    for (size_t i = 0; i < rows.size(); ++i) byScene[rows[i].scene].push_back(i);
    for (auto& [scene, idx] : byScene) {
        std::vector<double> t, e;
        for (size_t i : idx) {
            t.push_back(rows[i].frameMs);
            e.push_back(rows[i].errorPixels);
        }
        const std::vector<bool> on = paretoFront(t, e);
        for (size_t k = 0; k < idx.size(); ++k) rows[idx[k]].onFront = on[k];
    }
}

std::string csvHeader() {
    return "scene,method,conservative,default,views,rounds,width,height,cull_ms_median,frame_ms_median,"
           "cull_ratio_to_none,frame_ratio_to_none,objects_mean,triangles_mean,error_pixels_mean,error_percent,"
           "views_with_error,wrongly_culled_mean,wrongly_culled_total,on_front";
}

std::string csv(const std::vector<Row>& rows) {
    std::string s = csvHeader() + "\n";
    for (const Row& w : rows) {
        s += w.scene + "," + w.method + "," + (w.conservative ? "yes" : "no") + "," + (w.isDefault ? "yes" : "no") +
             "," + std::to_string(w.views) + "," + std::to_string(w.rounds) + "," + std::to_string(w.width) + "," +
             std::to_string(w.height) + "," + fixed(w.cullMs, 4) + "," + fixed(w.frameMs, 3) + "," +
             fixed(w.cullRatio, 4) + "," + fixed(w.frameRatio, 4) + "," + fixed(w.objects, 1) + "," +
             fixed(w.triangles, 1) + "," + fixed(w.errorPixels, 2) + "," + fixed(w.errorPercent, 5) + "," +
             std::to_string(w.viewsWithError) + "," + fixed(w.wronglyCulled, 3) + "," +
             std::to_string(w.wronglyCulledTotal) + "," + (w.onFront ? "yes" : "no") + "\n";
    }
    return s;
}

std::string markdown(const std::vector<Row>& rows) {
    std::string s;
    std::string scene;
    for (const Row& w : rows) {
        if (w.scene != scene) {
            scene = w.scene;
            s += (s.empty() ? "" : "\n") + std::string("### ") + scene + " (" + std::to_string(w.views) + " views at " +
                 std::to_string(w.width) + "x" + std::to_string(w.height) + ", " + std::to_string(w.rounds) +
                 (w.rounds == 1 ? " round" : " rounds") + ")\n\n";
            s += "| method | conservative | cull ms | frame ms | frame / none | objects | triangles | differing "
                 "pixels per view (% of frame) | views with error | wrongly culled per view | front |\n";
            s += "|---|---|---|---|---|---|---|---|---|---|---|\n";
        }
        const std::string name = w.method + (w.isDefault ? " (CullSettings{})" : "");
        s += "| " + (w.onFront ? "**" + name + "**" : name) + " | " + (w.conservative ? "yes" : "no") + " | " +
             fixed(w.cullMs, 3) + " | " + fixed(w.frameMs, 2) + " | " + fixed(w.frameRatio, 3) + " | " +
             fixed(w.objects, 0) + " | " + fixed(w.triangles, 0) + " | " + fixed(w.errorPixels, 1) + " (" +
             fixed(w.errorPercent, 3) + "%) | " + std::to_string(w.viewsWithError) + " | " + fixed(w.wronglyCulled, 2) +
             " | " + (w.onFront ? "yes" : "") + " |\n";
    }
    return s;
}

std::vector<OffFront> defaultOffFront(const std::vector<Row>& rows, double tolerance) {
    std::vector<OffFront> out;
    for (const Row& d : rows) {
        if (!d.isDefault || d.onFront) continue;
        std::string by;
        bool beyond = false;
        for (const Row& w : rows) {
            if (w.scene != d.scene || !(w.frameMs < d.frameMs) || !(w.errorPixels <= d.errorPixels)) continue;
            double ratio = w.frameMs / d.frameMs;
            std::string paired;
            if (!w.frames.empty() && w.frames.size() == d.frames.size()) {
                std::vector<double> r;
                size_t faster = 0;
                for (size_t i = 0; i < w.frames.size(); ++i) {
                    r.push_back(w.frames[i] / d.frames[i]);
                    faster += w.frames[i] < d.frames[i];
                }
                ratio = stats::median(r);
                paired = ", frame by frame " + fixed(100.0 * (ratio - 1.0), 1) + "% (median), faster in " +
                         std::to_string(faster) + " of " + std::to_string(r.size());
            }
            beyond = beyond || ratio < 1.0 - tolerance;
            by += (by.empty() ? "" : "; ") + w.method + " (" + fixed(w.frameMs, 2) + " ms, " +
                  fixed(100.0 * (w.frameMs / d.frameMs - 1.0), 1) + "%, error " + fixed(w.errorPixels, 1) + paired +
                  ")";
        }
        out.push_back({d.scene, beyond,
                       d.scene + ": the default (" + fixed(d.frameMs, 2) + " ms, error " + fixed(d.errorPixels, 1) +
                           ") is beaten by " + by});
    }
    return out;
}

std::string gnuplotScript(const std::vector<Row>& rows, const std::string& png) {
    bool ratios = true;
    for (const Row& w : rows) ratios = ratios && w.frameRatio > 0;
    std::vector<std::string> scenes;
    for (const Row& w : rows)
        if (std::find(scenes.begin(), scenes.end(), w.scene) == scenes.end()) scenes.push_back(w.scene);
    std::string s =
        "# sgbench pareto: frame time against error, one colour per scene, each scene's Pareto front joined.\n"
        "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
        "  set terminal pngcairo size 960,600 font ',9'\n"
        "} else {\n"
        "  set terminal png size 960,600\n"
        "}\n"
        "set output '" +
        png +
        "'\n"
        "set logscale x\nset logscale y\nset grid\nset key outside right top\n"
        "set autoscale fix\nset offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05\n"
        "set xlabel 'differing pixels per view + 1 (against the unculled full-detail render)'\n"
        "set ylabel '" +
        std::string(ratios ? "frame ms over the frame ms of none (medians)" : "frame ms (median)") + "'\n";
    std::string plot;
    for (size_t k = 0; k < scenes.size(); ++k) {
        std::vector<const Row*> pts, front;
        for (const Row& w : rows)
            if (w.scene == scenes[k]) {
                pts.push_back(&w);
                if (w.onFront) front.push_back(&w);
            }
        std::sort(front.begin(), front.end(),
                  [](const Row* a, const Row* b) { return a->errorPixels < b->errorPixels; });
        auto block = [&](const std::string& name, const std::vector<const Row*>& v) {
            s += "$" + name + " << EOD\n";
            for (const Row* w : v)
                s += fixed(w->errorPixels + 1.0, 3) + " " + fixed(ratios ? w->frameRatio : w->frameMs, 5) + " \"" +
                     w->method + "\"\n";
            s += "EOD\n";
        };
        const std::string id = std::to_string(k);
        block("all" + id, pts);
        block("front" + id, front);
        const std::string lc = " lc " + std::to_string(k + 1);
        plot += std::string(plot.empty() ? "plot " : ", \\\n     ") + "$all" + id +
                " using 1:2 with points pt 7 ps 1.2" + lc + " title '" + scenes[k] + "', \\\n     $front" + id +
                " using 1:2 with lines" + lc + " notitle, \\\n     $front" + id +
                " using 1:2:3 with labels offset 1,0.5 left font ',7' tc lt " + std::to_string(k + 1) + " notitle";
    }
    // The default of every scene, ringed.
    s += "$default << EOD\n";
    for (const Row& w : rows)
        if (w.isDefault) s += fixed(w.errorPixels + 1.0, 3) + " " + fixed(ratios ? w.frameRatio : w.frameMs, 5) + "\n";
    s += "EOD\n";
    plot += ", \\\n     $default using 1:2 with points pt 6 ps 2.4 lc rgb 'black' title 'default (CullSettings{})'";
    return s + plot + "\n";
}

}  // namespace pareto
