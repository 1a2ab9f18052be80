#!/usr/bin/env bash
# The viewer's threading models against SingleThreaded (sgbench frame, each run interleaving the two pass by pass):
# the city orbit at N=316 and N=1000 and the factory's walk, with llvmpipe's default rasterizer threads and with one
# (LP_NUM_THREADS=1); two views culled per frame (cull-per-view); an application with work of its own each frame;
# the collider's step in the app stage or on the ISECT thread. A markdown table on stdout.
#   bench/threading.sh BUILD_DIR        (ROUNDS=3 FRAMES=120 by default)
set -euo pipefail
build=${1:?build directory}
rounds=${ROUNDS:-3}
frames=${FRAMES:-120}
out=${OUT:-threading}
sg() { "$build/bench/sgbench" frame --rounds "$rounds" --frames "$frames" --json "$@"; }
{
  run() {  # LP ARGS...: one sgbench frame run, its llvmpipe thread setting added to the JSON
    local lp=$1
    shift
    if [[ $lp == default ]]; then sg "$@"; else LP_NUM_THREADS=$lp sg "$@"; fi | sed "s/^{/{\"lp_threads\": \"$lp\", /"
  }
  for lp in default 1; do
    for scene in "--scene city --n 316" "--scene city --n 1000" "--scene factory"; do run $lp $scene --threading draw; done
    for scene in "--scene city --n 316" "--scene factory"; do run $lp $scene --threading app-cull-draw; done
    run $lp --scene city --n 316 --views 2 --threading cull-per-view
  done
  # An application with work of its own each frame (--app-ms): what the pipeline overlaps with the draw.
  run 1 --scene factory --app-ms 20 --threading draw
  run 1 --scene factory --app-ms 20 --threading app-cull-draw
  run 1 --scene city --n 316 --app-ms 40 --threading draw
  for c in sync async; do run default --scene city --n 316 --path street --threading draw --collide "$c"; done
} > "$out.jsonl"
python3 - "$out.jsonl" <<'PY'
import json, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
print("| scene | llvmpipe threads | views | app work ms | collide | model | latency | single period ms | model period ms | fps x single (min-max) | app / cull / draw ms (model) | period / slowest stage | cull wall x single |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    scene = r["scene"] + (" N=%d" % r["n"] if r["n"] else "") + " " + r["path"]
    print("| %s | %s | %d | %s | %s | %s | %d | %.1f | %.1f | %.2f (%.2f-%.2f) | %.2f / %.2f / %.1f | %.2f | %.2f |" % (
        scene, r["lp_threads"], r["views"], "%g" % r["app_work_ms"], r["collide"], r["threading"], r["latency_frames"],
        r["single_period_ms"], r["model_period_ms"], r["fps_ratio_model_over_single"], r["fps_ratio_min"],
        r["fps_ratio_max"], r["model_app_ms"], r["model_cull_ms"], r["model_draw_ms"],
        r["model_period_over_slowest_stage"], r["cull_wall_ratio_model_over_single"]))
for r in runs:
    if r["collide"] != "none":
        print("collide %s: app stage single %.3f ms, model %.3f ms; collision step %.3f ms (%s)" % (
            r["collide"], r["single_app_ms"], r["model_app_ms"], r["model_isect_ms"],
            "in the app stage" if r["collide"] == "sync" else "on the ISECT thread, answered a frame later"))
PY
