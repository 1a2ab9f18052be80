#!/usr/bin/env bash
# The point cloud chain end to end: the factory's simulated laser scan written as LAS (factoryscan), tiled as a
# 3D Tiles octree of glTF point tiles (sgtile --points, under /usr/bin/time -v: points per second, peak resident
# memory), then flown from disk along the factory walkthrough (sgbench tiles --path factory-walk --settle-check),
# with 1 px squares and with eye-dome lighting. One JSON line per step to $OUT/points.jsonl; a settled view whose
# picture differs from the same tiles held in memory makes the script exit 1 (after every step has run).
#   bench/points.sh BUILD_DIR [POINTS] [FRAMES]      POINTS as factoryscan takes it (10M, 1G); OUT=points by default
set -euo pipefail
build=${1:?build directory}
points=${2:-10M}
frames=${3:-1200}
out=${OUT:-points}
mkdir -p "$out"
jsonl="$out/points.jsonl"
: > "$jsonl"

"$build/examples/factoryscan" --points "$points" --out "$out/scan.las" | tee "$out/factoryscan.txt"
rm -rf "$out/scan-tiles"
/usr/bin/time -v "$build/examples/sgtile" --points "$out/scan.las" --out "$out/scan-tiles" \
  > "$out/sgtile.txt" 2> "$out/sgtile-time.txt"
cat "$out/sgtile.txt"

# factoryscan's and sgtile's figures as JSON lines: the scan's own count and time; sgtile's points over its wall time
# as /usr/bin/time measured it (the process's start and the writing of tileset.json included), and its peak RSS.
python3 - "$out" >> "$jsonl" <<'PY'
import json, re, sys
out = sys.argv[1]
def find(path, pattern, kind=float):
    m = re.search(pattern, open(path).read(), re.M)
    return kind(m.group(1)) if m else None
scan = out + "/factoryscan.txt"
print(json.dumps({"command": "factoryscan", "points": find(scan, r"^points written: (\d+)", int),
                  "seconds": find(scan, r"^seconds: ([\d.]+)"), "points_per_s": find(scan, r"^points per second: ([\d.]+)")}))
timing = out + "/sgtile-time.txt"
wall = None
m = re.search(r"Elapsed \(wall clock\) time[^:]*: (?:(\d+):)?(\d+):([\d.]+)", open(timing).read())
if m:
    wall = int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3))
n = find(out + "/sgtile.txt", r": (\d+) points,", int)
rss = find(timing, r"Maximum resident set size \(kbytes\): (\d+)", int)
print(json.dumps({"command": "sgtile", "points": n, "wall_s": wall,
                  "points_per_s": n / wall if n and wall else None,
                  "tiles": find(out + "/sgtile.txt", r", (\d+) tiles,", int),
                  "max_rss_mb": rss / 1024.0 if rss else None}))
PY

status=0
for mode in plain edl; do
  edl=""
  if [ "$mode" = edl ]; then edl="--edl"; fi
  # shellcheck disable=SC2086 # an empty $edl is no argument at all
  "$build/bench/sgbench" tiles --tileset "$out/scan-tiles/tileset.json" --path factory-walk --frames "$frames" --resident-mb 48 \
    --settle-check --png "$out/differs-$mode-" $edl --json >> "$jsonl" || status=1
done
cat "$jsonl"
exit $status
