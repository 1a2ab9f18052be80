#!/usr/bin/env bash
# Checks that two builds give the same deterministic figures (what is culled, drawn, occluded, picked and
# the differing pixels; times and memory left out): for changes meant to keep behaviour, such as a
# restructuring. Runs one set of sgbench commands on each build, then compares the JSON field by field.
#   bench/same_figures.sh BASE_BUILD_DIR NEW_BUILD_DIR      (about 3 minutes)
set -euo pipefail
base=${1:?base build directory}
new=${2:?new build directory}
out=${OUT:-same-figures}
run() {
  local s="$1/bench/sgbench"
  for st in aabb sphere sphere-sphere center-box; do "$s" cull --scene city --n 100 --strategy "$st" --json; done
  "$s" cull --scene city --n 100 --path street --json
  for st in none sphere aabb sphere-sphere center-box; do "$s" accuracy --scene city --n 24 --views 40 --strategy "$st" --json; done
  "$s" accuracy --scene city --n 24 --views 40 --strategy sphere --small-feature 2 --json
  "$s" accuracy --scene random --views 40 --strategy aabb --json
  # "tree" is every-frame's older spelling, which builds from before the rename take too.
  "$s" accuracy --scene office --r 4 --views 40 --strategy aabb --occlusion tree --json
  "$s" accuracy --scene city --n 24 --views 40 --strategy aabb --occlusion tree --json
  "$s" occlusion --scene city --n 100 --path street --ideal --json
  "$s" occlusion --scene office --r 8 --path walk --ideal --json
  for sp in 0 2 4; do "$s" occlusion --scene city --n 100 --path street --no-draw --splits "$sp" --json; done
  "$s" lod --scene city --n 100 --budget-ms 33 --method static --every 8 --json
  "$s" pick --scene city --n 32 --json
}
run "$base" > "$out.base.jsonl"
run "$new" > "$out.new.jsonl"
python3 - "$out.base.jsonl" "$out.new.jsonl" <<'PY'
import json, sys
load = lambda p: [json.loads(l) for l in open(p) if l.startswith("{")]
a, b = load(sys.argv[1]), load(sys.argv[2])
timing = ("ms", "_s", "_us", "rss", "bytes", "speedup", "per_s", "time", "ratio")
renamed = {"tree": "every-frame", "auto": "adaptive"}  # the occlusion modes' names before and after
for r in a + b:
    if "occlusion" in r: r["occlusion"] = renamed.get(r["occlusion"], r["occlusion"])
bad = 0 if len(a) == len(b) else 1
for i, (x, y) in enumerate(zip(a, b)):
    for k in sorted(set(x) | set(y)):
        if not any(t in k for t in timing) and x.get(k) != y.get(k):
            print("run %d (%s) %s: %s -> %s" % (i + 1, x.get("command"), k, x.get(k), y.get(k)))
            bad += 1
print("%d runs compared, %d differences" % (len(a), bad))
sys.exit(1 if bad else 0)
PY
