#!/usr/bin/env bash
# Paging ahead along the camera's motion (docs/benchmarks.md, "Looking ahead"): a tileset flown with and without
# View::prefetchSeconds, alternating (A B A B ...) so that both see the same machine speed, each frame compared with
# the city held in memory (--baseline). Prints one JSON line per run; the en-route figures count the frames after the
# first view settled (the start's own load aside).
#   bench/tiles_lookahead.sh BUILD_DIR TILESET_JSON N [PATH FRAMES]
set -euo pipefail
build=${1:?build directory}
tileset=${2:?tileset.json written by sgtile}
n=${3:?the city size it was written at}
path=${4:-low}
frames=${5:-300}
rounds=${ROUNDS:-3}
seconds=${SECONDS_AHEAD:-1}
for r in $(seq "$rounds"); do
  for p in 0 "$seconds"; do
    "$build/bench/sgbench" tiles --tileset "$tileset" --n "$n" --path "$path" --frames "$frames" --baseline \
      --prefetch "$p" --json
  done
done
