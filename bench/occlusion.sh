#!/usr/bin/env bash
# The occlusion-tree figures: city N=100 street path and office R=8 walk (triangles left after frustum
# culling and after occlusion, pass and frame times, the exact visible set for reference), then the
# one- and two-level trees, interleaved (A B C A B C ...) so that all see the same machine speed.
#   bench/occlusion.sh BUILD_DIR
set -euo pipefail
build=${1:?build directory}
rounds=${ROUNDS:-3}
sgbench="$build/bench/sgbench"
{
  "$sgbench" occlusion --scene city --n 100 --path street --ideal --json
  "$sgbench" occlusion --scene office --r 8 --path walk --ideal --json
  for r in $(seq "$rounds"); do
    for s in 0 2 4; do
      "$sgbench" occlusion --scene city --n 100 --path street --no-draw --splits "$s" --json
      "$sgbench" occlusion --scene office --r 8 --path walk --no-draw --splits "$s" --json
    done
  done
} | python3 -c '
import json, statistics, sys
runs = [json.loads(l) for l in sys.stdin if l.startswith("{")]
full = [r for r in runs if "frame_ms_median_frustum" in r]
print("| scene, path | triangles (no culling) | after frustum | after occlusion | exact visible set | occlusion / frustum | pass ms (median) | cull ms frustum / with pass | frame ms frustum / with pass | frame speed-up (median per frame) | occluders used |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in full:
    size = "N=%d" % r["n"] if "n" in r else "R=%d" % r["r"]
    print("| %s %s, %s | %.0f | %.0f (%.1f%%) | %.0f (%.2f%%) | %.0f (%.2f%%) | %.3f | %.3f | %.3f / %.3f | %.1f / %.1f | %.2fx | %.1f |" % (
        r["scene"], size, r["path"], r["triangles_total"], r["triangles_frustum_mean"], r["frustum_percent"],
        r["triangles_occlusion_mean"], r["occlusion_percent"], r["triangles_visible_mean"], r["visible_percent"],
        r["occlusion_over_frustum"], r["occlusion_ms_median"], r["cull_ms_median_frustum"], r["cull_ms_median_occlusion"],
        r["frame_ms_median_frustum"], r["frame_ms_median_occlusion"], r["frame_speedup_median"], r["occluders_used_mean"]))
print()
print("| scene | screen splits (two-level tree) | pass ms (median of runs) | tree nodes | polygon splits | box splits | occlusion / frustum |")
print("|---|---|---|---|---|---|---|")
two = [r for r in runs if "frame_ms_median_frustum" not in r]
for scene in ("city", "office"):
    for s in (0, 2, 4):
        rs = [r for r in two if r["scene"] == scene and r["splits"] == s]
        if not rs: continue
        print("| %s | %d | %.3f | %.0f | %.0f | %.0f | %.3f |" % (scene, s, statistics.median(r["occlusion_ms_median"] for r in rs),
              rs[0]["tree_nodes_mean"], rs[0]["polygon_splits_mean"], rs[0]["box_splits_mean"], rs[0]["occlusion_over_frustum"]))
'
