#!/usr/bin/env bash
# LOD selection against a frame budget on city's orbit path: static ranges, Performer's stress, and the
# time budget (with and without leaving LODs out), for several budgets; frame time and image error against
# full detail, a table and a plot (gnuplot, if installed) of frame time against image error.
#   bench/lod.sh BUILD_DIR [N] [EVERY]
set -euo pipefail
build=${1:?build directory}
n=${2:-100}
every=${3:-4}
out=${OUT:-lod}
{
  for b in 20 33 50; do
    for m in static stress budget; do "$build/bench/sgbench" lod --scene city --n "$n" --budget-ms "$b" --method "$m" --every "$every" --json; done
    "$build/bench/sgbench" lod --scene city --n "$n" --budget-ms "$b" --method budget --no-drop --every "$every" --json
  done
} > "$out.jsonl"
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
runs = [json.loads(l) for l in open(out + ".jsonl")]
print("| budget ms | method | frame ms mean | p95 | p95 abs(frame - budget) | image MAE (0-255) | pixels differing | triangles | LODs dropped | select ms |")
print("|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    m = r["method"] + (" + drop" if r.get("may_drop") == "yes" else "")
    print("| %g | %s | %.1f | %.1f | %.1f | %.3f | %.2f%% | %.0f | %.0f | %.3f |" % (r["budget_ms"], m, r["frame_ms_mean"], r["frame_ms_p95"],
          r["budget_abs_dev_p95_ms"], r["image_mae"], r["image_pct_differing"], r["triangles_mean"], r["dropped_mean"], r["select_ms_median"]))
with open(out + ".dat", "w") as f:
    for m in ("static", "stress", "budget", "budget + drop"):
        f.write('"%s"\n' % m)
        for r in runs:
            if r["method"] + (" + drop" if r.get("may_drop") == "yes" else "") == m:
                f.write("%g %g\n" % (r["frame_ms_mean"], r["image_mae"]))
        f.write("\n\n")
PY
if command -v gnuplot >/dev/null; then
  gnuplot <<GP
set terminal pngcairo size 800,500
set output "$out.png"
set xlabel "frame time, ms (mean over the path)"
set ylabel "image error against full detail (mean abs. difference, 0-255)"
set key top right
set logscale x
plot for [i=0:3] "$out.dat" index i using 1:2 with linespoints title columnheader(1)
GP
  echo "plot: $out.png"
fi
