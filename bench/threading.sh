#!/usr/bin/env bash
# The viewer's threading models against SingleThreaded (sgbench frame, each run interleaving the two pass by pass):
# the city orbit at N=316 and N=1000 and the factory's walk, with llvmpipe's default rasterizer threads and with one
# (LP_NUM_THREADS=1: the rasterizer on one core, the cull free to take the other); two views culled per frame
# (cull-per-view); the collider's step in the app stage or on the ISECT thread. A markdown table on stdout.
#   bench/threading.sh BUILD_DIR        (ROUNDS=3 FRAMES=120 by default)
set -euo pipefail
build=${1:?build directory}
rounds=${ROUNDS:-3}
frames=${FRAMES:-120}
out=${OUT:-threading}
sg() { "$build/bench/sgbench" frame --rounds "$rounds" --frames "$frames" --json "$@"; }
{
  for lp in default 1; do
    for m in draw cull-per-view app-cull-draw; do
      for scene in "--scene city --n 316" "--scene city --n 1000" "--scene factory"; do
        if [[ $lp == default ]]; then sg $scene --threading "$m"; else LP_NUM_THREADS=1 sg $scene --threading "$m"; fi |
          sed "s/^{/{\"lp_threads\": \"$lp\", /"
      done
    done
    # The time budget on: the draw held near the period, cull and draw within 2x of each other.
    if [[ $lp == default ]]; then sg --scene city --n 1000 --threading draw --lod budget --budget-ms 33; else
      LP_NUM_THREADS=1 sg --scene city --n 1000 --threading draw --lod budget --budget-ms 33; fi | sed "s/^{/{\"lp_threads\": \"$lp\", /"
  done
  sg --scene city --n 316 --views 2 --threading cull-per-view | sed 's/^{/{"lp_threads": "default", /'
  LP_NUM_THREADS=1 sg --scene city --n 316 --views 2 --threading cull-per-view | sed 's/^{/{"lp_threads": "1", /'
  for c in sync async; do
    sg --scene city --n 316 --path street --threading draw --collide "$c" | sed 's/^{/{"lp_threads": "default", /'
  done
} > "$out.jsonl"
python3 - "$out.jsonl" <<'PY'
import json, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
print("| scene | llvmpipe threads | views | LOD | collide | model | latency | single period ms | model period ms | fps x single (min-max) | app / cull / draw ms (model) | period / slowest stage | cull wall x single |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    scene = r["scene"] + (" N=%d" % r["n"] if r["n"] else "") + " " + r["path"]
    print("| %s | %s | %d | %s | %s | %s | %d | %.1f | %.1f | %.2f (%.2f-%.2f) | %.2f / %.2f / %.1f | %.2f | %.2f |" % (
        scene, r["lp_threads"], r["views"], r["lod"], r["collide"], r["threading"], r["latency_frames"],
        r["single_period_ms"], r["model_period_ms"], r["fps_ratio_model_over_single"], r["fps_ratio_min"],
        r["fps_ratio_max"], r["model_app_ms"], r["model_cull_ms"], r["model_draw_ms"],
        r["model_period_over_slowest_stage"], r["cull_wall_ratio_model_over_single"]))
for r in runs:
    if r["collide"] != "none":
        print("collide %s: app stage single %.3f ms, model %.3f ms; collision step %.3f ms (%s)" % (
            r["collide"], r["single_app_ms"], r["model_app_ms"], r["model_isect_ms"],
            "in the app stage" if r["collide"] == "sync" else "on the ISECT thread, answered a frame later"))
PY
