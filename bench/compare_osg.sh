#!/usr/bin/env bash
# Interleaves sgbench cull and the OpenSceneGraph peer on city's orbit path (A B A B ...), so that both
# see the same machine speed, and prints each run and the ratios of the medians.
#   bench/compare_osg.sh BUILD_DIR [N ...]     (BUILD_DIR configured with -DSGKIT_BENCH_OSG=ON)
set -euo pipefail
build=${1:?build directory}
shift
sizes=${*:-316 1000}
rounds=${ROUNDS:-3}
for r in $(seq "$rounds"); do
  for n in $sizes; do
    "$build/bench/sgbench" cull --scene city --n "$n" --json
    "$build/bench/osg_peer/sgbench_osg" --n "$n"
  done
done | python3 -c '
import json, statistics, sys
runs = [json.loads(l) for l in sys.stdin if l.startswith("{")]
for r in runs:
    who = r.get("peer", "sgkit")
    print("%-14s n=%5d cull_ms_median=%8.3f p95=%8.3f geometries=%9.1f bytes_per_node=%6.1f build_s=%.2f" % (
          who, r["n"], r["cull_ms_median"], r["cull_ms_p95"], r["geometries_mean"], r["bytes_per_node"], r["build_s"]))
print()
for n in sorted({r["n"] for r in runs}):
    sg = [r["cull_ms_median"] for r in runs if r["n"] == n and "peer" not in r]
    osg = [r["cull_ms_median"] for r in runs if r["n"] == n and "peer" in r]
    pairs = [o / s for s, o in zip(sg, osg)]
    print(f"n={n}: sgkit {statistics.median(sg):.3f} ms, OpenSceneGraph {statistics.median(osg):.3f} ms, "
          f"OpenSceneGraph/sgkit per pair {[round(p, 1) for p in pairs]}, median {statistics.median(pairs):.1f}x")
ns = sorted({r["n"] for r in runs})
if len(ns) > 1:
    for who in ("sgkit", "openscenegraph"):
        per = {n: [r["cull_ms_median"] for r in runs if r["n"] == n and r.get("peer", "sgkit") == who] for n in ns}
        ratios = [b / a for a, b in zip(per[ns[0]], per[ns[-1]])]
        print(f"{who}: n={ns[-1]} / n={ns[0]} cull time per round {[round(x, 2) for x in ratios]}, median {statistics.median(ratios):.2f}x")
'
