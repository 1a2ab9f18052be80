#include "factory/Report.h"
#include "testbed/Stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace factory {

double jitterP95(const std::vector<double>& frameMs) {
    const double m = stats::median(frameMs);
    std::vector<double> d;
    for (double t : frameMs) d.push_back(std::abs(t - m));
    return stats::percentile(d, 0.95);
}

ModeSummary summarize(const ModeRun& run) {
    ModeSummary s;
    s.name = sg::lodPolicyName(run.mode);
    s.budgetMs = run.budgetMs;
    std::vector<double> frame, fps, dev, work;
    double draw = 0, tris = 0, verts = 0, mae = 0, reducedMs = 0;
    int compared = 0, reduced = 0;
    for (const FrameRecord& r : run.frames) {
        frame.push_back(r.frameMs);
        work.push_back(r.workMs);
        s.workMsMean += r.workMs;
        fps.push_back(1000.0 / std::max(1e-6, r.frameMs));
        dev.push_back(std::abs(r.frameMs - run.budgetMs));
        draw += r.drawMs;
        tris += double(r.triangles);
        verts += double(r.vertices);
        if (r.mae >= 0) {
            mae += r.mae;
            ++compared;
            if (r.mae == 0.0) {
                ++s.fullDetailFrames;
            } else {
                reducedMs += r.frameMs;
                ++reduced;
            }
        }
    }
    const double n = std::max<double>(1.0, double(run.frames.size()));
    s.fpsMedian = stats::median(fps);
    s.frameMsMedian = stats::median(frame);
    for (double t : frame) s.frameMsMean += t / n;
    s.frameMsP95 = stats::percentile(frame, 0.95);
    s.drawMsMean = draw / n;
    s.workMsMean /= n;
    s.workMsP95 = stats::percentile(work, 0.95);
    s.trianglesMean = tris / n;
    s.verticesMean = verts / n;
    s.imageMae = compared ? mae / compared : -1.0;
    s.budgetAbsDevP95 = stats::percentile(dev, 0.95);
    s.frameMsMeanReduced = reduced ? reducedMs / reduced : -1.0;
    return s;
}

void writeCsv(const std::string& file, const scenes::WalkPath& path, const std::vector<ModeRun>& runs) {
    std::FILE* f = std::fopen(file.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + file);
    std::fprintf(f,
                 "mode,frame,segment,workshop,eye_x,eye_y,eye_z,triangles,vertices,geometries,cull_ms,draw_ms,"
                 "work_ms,frame_ms,predicted_ms,image_mae\n");
    for (const ModeRun& run : runs)
        for (const FrameRecord& r : run.frames) {
            const scenes::PathFrame& p = path.frames[size_t(r.frame)];
            std::fprintf(f, "%s,%d,%s,%d,%.3f,%.3f,%.3f,%llu,%llu,%llu,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f\n",
                         sg::lodPolicyName(run.mode), r.frame, p.segment.c_str(), p.workshop, p.eye.x, p.eye.y, p.eye.z,
                         (unsigned long long)r.triangles, (unsigned long long)r.vertices,
                         (unsigned long long)r.geometries, r.cullMs, r.drawMs, r.workMs, r.frameMs, r.predictedMs,
                         r.mae);
        }
    if (std::fclose(f) != 0) throw std::runtime_error("cannot write " + file);
}

void printTable(std::FILE* out, const Summary& s) {
    std::fprintf(out, "factory walkthrough: %d frames at %dx%d, site %llu triangles stored\n", s.frames, s.width,
                 s.height, (unsigned long long)s.trianglesTotal);
    std::fprintf(out, "  eye inside a workshop %d frames, collision penetrations %d, same-view jitter p95 %.2f ms\n",
                 s.switchInsideFrames, s.penetrations, s.sameViewJitterP95Ms);
    std::fprintf(out, "%-30s %10s %10s %10s %10s %8s %10s %9s\n", "", "visible", "visible", "draw", "frame", "frame",
                 "frame p95", "image");
    std::fprintf(out, "%-30s %10s %10s %10s %10s %8s %10s %9s\n", "", "triangles", "vertices", "ms (mean)", "ms (mean)",
                 "rate/s", "ms", "MAE");
    for (const ModeSummary& m : s.modes) {
        const std::string label =
            m.name == "budget" ? "budget " + std::to_string(int(std::lround(m.budgetMs))) + " ms" : m.name;
        std::fprintf(out, "%-30s %10.0f %10.0f %10.1f %10.1f %8.1f %10.1f %9.3f\n", ("sgkit " + label).c_str(),
                     m.trianglesMean, m.verticesMean, m.drawMsMean, m.frameMsMean, m.fpsMedian, m.frameMsP95,
                     m.imageMae);
    }
    // Table 1 of the paper: the factory site on an SGI Indigo2/Extreme, 1070x865, two measured views.
    std::fprintf(out, "%-30s %10d %10d %10.1f %10.1f %8.1f %10s %9s\n", "paper (Indigo2/Extreme)", 3817, 7071, 57.6,
                 68.9, 14.2, "-", "-");
    std::fprintf(out, "%-30s %10d %10d %10.1f %10.1f %8.1f %10s %9s\n", "paper (Indigo2/Extreme)", 5243, 9889, 71.5,
                 83.0, 11.8, "-", "-");
    std::fprintf(out,
                 "  (sgkit: means over the path; frame rate is the median of 1000 / frame time; budget and stress\n"
                 "   hold the frame rate: a frame done early waits out the budget, which the frame time counts)\n");
}

void printJson(std::FILE* out, const Summary& s) {
    std::fprintf(out, "{\"width\": %d, \"height\": %d, \"frames\": %d, \"triangles_total\": %llu, ", s.width, s.height,
                 s.frames, (unsigned long long)s.trianglesTotal);
    std::fprintf(out,
                 "\"penetrations\": %d, \"switch_inside_frames\": %d, \"same_view_jitter_p95_ms\": %.4f, "
                 "\"background_load\": \"%s\"",
                 s.penetrations, s.switchInsideFrames, s.sameViewJitterP95Ms, s.backgroundLoad.c_str());
    for (const ModeSummary& m : s.modes) {
        std::fprintf(out,
                     ", \"%s\": {\"fps_median\": %.3f, \"frame_ms_median\": %.4f, \"frame_ms_mean\": %.4f, "
                     "\"frame_ms_p95\": %.4f, \"draw_ms_mean\": %.4f, \"triangles_visible_mean\": %.1f, "
                     "\"vertices_visible_mean\": %.1f, \"image_mae\": %.5f, \"work_ms_mean\": %.4f, "
                     "\"work_ms_p95\": %.4f",
                     m.name.c_str(), m.fpsMedian, m.frameMsMedian, m.frameMsMean, m.frameMsP95, m.drawMsMean,
                     m.trianglesMean, m.verticesMean, m.imageMae, m.workMsMean, m.workMsP95);
        if (m.name == "budget")
            std::fprintf(out,
                         ", \"budget_ms\": %.3f, \"budget_abs_dev_p95_ms\": %.4f, \"full_detail_frames\": %d, "
                         "\"frame_ms_mean_reduced\": %.4f",
                         m.budgetMs, m.budgetAbsDevP95, m.fullDetailFrames, m.frameMsMeanReduced);
        std::fprintf(out, "}");
    }
    std::fprintf(out, "}\n");
}

}  // namespace factory
