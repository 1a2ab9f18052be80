#!/usr/bin/env bash
# Two builds' whole frames, alternating in one script (this machine's speed drifts for seconds at a time): the
# factory walkthrough's static median frame, p95 and image error (`factory --headless --json`, full path), the city
# N=32 flight's wall time per frame (`cityflight --frames 300`) and the map's frame rates at the world and U.S.
# levels (bench/map/map_memory.sh). Compare the ratios of each round.
#   bench/old_new_frames.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS [MAP_LEVELS_DIR]]
set -euo pipefail
old=${1:?usage: old_new_frames.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS [MAP_LEVELS_DIR]]}
new=${2:?usage: old_new_frames.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS [MAP_LEVELS_DIR]]}
old=$(cd "$old" && pwd)  # absolute: the runs below change directory
new=$(cd "$new" && pwd)
rounds=${3:-3}
data=${4:-$new/mapdata/levels}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for round in $(seq "$rounds"); do
  for which in old new; do
    build=${!which}
    (cd "$work" && "$build/examples/factory" --headless --json --out-dir "$work" --cache-dir "$work/cache-$which" \
      > "$work/factory.json" 2> /dev/null)
    factory=$(python3 -c '
import json, sys
s = json.load(open(sys.argv[1]))["static"]
print("static median %.2f ms, p95 %.2f ms, MAE %.3f" % (s["frame_ms_median"], s["frame_ms_p95"], s["image_mae"]))
' "$work/factory.json")
    t0=$(date +%s.%N)
    "$build/examples/cityflight" --n 32 --frames 300 --out "$work/city.png" > /dev/null
    t1=$(date +%s.%N)
    city=$(python3 -c "import sys; print('%.2f ms' % ((float(sys.argv[2]) - float(sys.argv[1])) * 1000 / 300))" "$t0" "$t1")
    map=$(bash "$here/map/map_memory.sh" "$build" "$data" | head -2 | tr '\n' ' ')
    echo "round $round $which: factory $factory | city per frame $city | map $map"
  done
done
