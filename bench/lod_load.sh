#!/usr/bin/env bash
# The LOD budget against stress under background load: sgbench lod on city N=100 and the factory at a 33 ms
# budget, budget and stress interleaved (and a second build's runs beside each, to compare two builds), on
# the machine as it is ("quiet"), with a thread spinning on another core ("spin": --background-load spin),
# and during a compile of this tree from scratch with -j2 ("compile": a scratch build directory, started
# before the runs and stopped after them). One JSON line per run in $OUT.jsonl, with the condition.
# A build older than --background-load ignores it: compare such a build under "spin" with an outside spinner
# (taskset -c 1 bash -c "while :; do :; done").
#   bench/lod_load.sh BUILD_DIR [OTHER_BUILD_DIR]      LOADS="quiet spin compile" EVERY=4 BUDGET=33
set -euo pipefail
builds=("$1")
[ $# -ge 2 ] && builds+=("$2")
loads=${LOADS:-quiet spin compile}
every=${EVERY:-4}
budget=${BUDGET:-33}
out=${OUT:-lod_load}
src=$(cd "$(dirname "$0")/.." && pwd)
: > "$out.jsonl"
for load in $loads; do
  flag=none compile=""
  [ "$load" = spin ] && flag=spin
  if [ "$load" = compile ]; then
    scratch=$(mktemp -d)
    cmake -S "$src" -B "$scratch" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
    setsid cmake --build "$scratch" -j2 >/dev/null 2>&1 &
    compile=$!
    sleep 30  # past the configure, into the compile
  fi
  for scene in city factory; do
    for method in budget stress; do
      for b in "${builds[@]}"; do
        r=$("$b/bench/sgbench" lod --scene "$scene" --n 100 --budget-ms "$budget" --method "$method" --every "$every" \
              --background-load "$flag" --json)
        echo "{\"load\": \"$load\", \"build\": \"$b\", \"loadavg\": $(cut -d' ' -f1 /proc/loadavg), \"run\": $r}" >> "$out.jsonl"
      done
    done
  done
  if [ -n "$compile" ]; then
    kill -- "-$compile" 2>/dev/null || true
    wait "$compile" 2>/dev/null || true
    rm -rf "$scratch"
  fi
done
python3 - "$out.jsonl" <<'PY'
import json, sys
print("| load | build | scene | method | frame ms mean | p95 abs(frame - budget) | same-view jitter p95 | image MAE | LODs dropped | load avg |")
print("|---|---|---|---|---|---|---|---|---|---|")
for l in open(sys.argv[1]):
    d = json.loads(l); r = d["run"]
    print("| %s | %s | %s | %s | %.1f | %.1f | %.1f | %.3f | %.0f | %.1f |" % (d["load"], d["build"], r["scene"], r["method"],
          r["frame_ms_mean"], r["budget_abs_dev_p95_ms"], r.get("same_view_jitter_p95_ms", float("nan")), r["image_mae"],
          r["dropped_mean"], d["loadavg"]))
PY
