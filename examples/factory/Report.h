// The walkthrough's report: the per-frame CSV, the summary table beside the paper's table 1, and the JSON.
#pragma once
#include "factory/Walkthrough.h"

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace factory {

struct ModeSummary {
    std::string name;
    double budgetMs = 0.0;
    double fpsMedian = 0, frameMsMedian = 0, frameMsMean = 0, frameMsP95 = 0, drawMsMean = 0;
    double workMsMean = 0, workMsP95 = 0;  // cull + draw, without the wait of a held frame rate
    double trianglesMean = 0, verticesMean = 0, imageMae = -1, budgetAbsDevP95 = 0;
    // Frames whose picture is the full-detail one (MAE 0: every LOD in view at its finest; a budget cannot make
    // them slower), and the mean frame time of the others (where a budget binds); -1 without compared frames.
    int fullDetailFrames = 0;
    double frameMsMeanReduced = -1;
};

struct Summary {
    int width = 0, height = 0, frames = 0;
    uint64_t trianglesTotal = 0;  // the site as stored (every distinct mesh once, at its finest level)
    int penetrations = 0, switchInsideFrames = 0;
    double sameViewJitterP95Ms = 0.0;
    std::string backgroundLoad = "none";  // BackgroundLoad::name() of the load the run competed with
    std::vector<ModeSummary> modes;
};

ModeSummary summarize(const ModeRun& run);
// p95 of |t - median(t)|.
double jitterP95(const std::vector<double>& frameMs);

// One row per mode and frame. Throws std::runtime_error naming the file when it cannot be written.
void writeCsv(const std::string& file, const scenes::WalkPath& path, const std::vector<ModeRun>& runs);
void printTable(std::FILE* out, const Summary& s);
void printJson(std::FILE* out, const Summary& s);

}  // namespace factory
