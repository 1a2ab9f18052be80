#!/usr/bin/env bash
# Run time against error for every cull strategy: cull time on city's orbit path (rounds interleaved
# across the strategies, so that all see the same machine speed) and differing pixels over random views.
#   bench/strategies.sh BUILD_DIR [N] [VIEWS]
set -euo pipefail
build=${1:?build directory}
n=${2:-316}
views=${3:-200}
rounds=${ROUNDS:-3}
strategies="none sphere aabb sphere-sphere center-box"
{
  for r in $(seq "$rounds"); do
    for s in $strategies; do "$build/bench/sgbench" cull --n "$n" --strategy "$s" --json; done
    "$build/bench/sgbench" cull --n "$n" --strategy sphere --small-feature 2 --json | sed 's/"strategy": "sphere"/"strategy": "sphere+small-feature-2px"/'
  done
  for s in $strategies; do "$build/bench/sgbench" accuracy --scene city --n 24 --views "$views" --strategy "$s" --json; done
  "$build/bench/sgbench" accuracy --scene city --n 24 --views "$views" --strategy sphere --small-feature 2 --json
} | python3 -c '
import json, statistics, sys
cull, acc = {}, {}
for line in sys.stdin:
    r = json.loads(line)
    if r["command"] == "cull":
        cull.setdefault(r["strategy"], []).append(r)
    else:
        acc[r["strategy"]] = r
print("| strategy | conservative | cull ms (median of runs) | vs none | geometries | views with error | differing pixels (% of frames) |")
print("|---|---|---|---|---|---|---|")
base = statistics.median(x["cull_ms_median"] for x in cull["none"])
for s, runs in cull.items():
    ms = statistics.median(x["cull_ms_median"] for x in runs)
    a = acc.get("sphere+small-feature" if "small" in s else s)
    err = "%d of %d | %d (%.4f%%)" % (a["views_with_error"], a["views"], a["differing_pixels_total"], a["differing_percent_of_frames"]) if a else "- | -"
    print("| %s | %s | %.3f | %.2fx | %.0f | %s |" % (s, a["conservative"] if a else "?", ms, ms / base, runs[0]["geometries_mean"], err))
'
