#!/usr/bin/env bash
# Whole frames of the city orbit in a 1280x720 window: sgkit's viewer (bench/frame/sgframe) against
# OpenSceneGraph's osgViewer (bench/osg_peer/sgframe_osg), each SingleThreaded and with a draw thread (sgkit's
# DrawThread, OSG's DrawThreadPerContext), alternating
# (A B C A B C ...) in one X server so that all see the same machine speed. Prints each run, then per size the
# medians of the runs' median frames and the ratio sgkit / OpenSceneGraph per round and its median.
#   bench/compare_osg_frame.sh BUILD_DIR [N ...]     (BUILD_DIR configured with -DSGKIT_BENCH_OSG=ON; ROUNDS=5)
# EXTRA=1 adds sgkit drawing every back face (--back-faces all) and OpenSceneGraph with a CullFace on its solids
# (--cull-face 1): each toolkit with and without skipping back faces. Without a display it starts Xvfb (xvfb-run).
set -euo pipefail
build=$(cd "${1:?build directory}" && pwd)
shift
sizes=${*:-100 316}
rounds=${ROUNDS:-5}
passes=${PASSES:-2}
for tool in "$build/bench/sgframe" "$build/bench/osg_peer/sgframe_osg"; do
  [[ -x $tool ]] || { echo "compare_osg_frame.sh: $tool is missing (configure with -DSGKIT_BENCH_OSG=ON)" >&2; exit 1; }
done
run() {
  for r in $(seq "$rounds"); do
    for n in $sizes; do
      "$build/bench/sgframe" --n "$n" --passes "$passes"
      "$build/bench/sgframe" --n "$n" --passes "$passes" --threading draw
      "$build/bench/osg_peer/sgframe_osg" --n "$n" --passes "$passes" --threading single
      "$build/bench/osg_peer/sgframe_osg" --n "$n" --passes "$passes" --threading draw
      if [[ -n ${EXTRA:-} ]]; then
        "$build/bench/sgframe" --n "$n" --passes "$passes" --back-faces all
        "$build/bench/osg_peer/sgframe_osg" --n "$n" --passes "$passes" --threading single --cull-face 1
      fi
    done
  done
}
if [[ -z ${DISPLAY:-} ]]; then  # again inside an X server of its own
  exec xvfb-run -a -s "-screen 0 1920x1080x24" "$0" "$build" $sizes
fi
out=$(run)
python3 -c '
import json, statistics, sys
runs = [json.loads(l) for l in sys.stdin if l.startswith("{")]
def who(r):
    if r["peer"] == "sgkit":
        return "sgkit" + ("" if r["back_faces"] == "auto" else " all-back-faces") + \
            ("" if r.get("threading", "single") == "single" else " " + r["threading"])
    return r["peer"] + " " + r["threading"]
for r in runs:
    g = r["geometries_mean"]
    print("%-26s n=%4d frame_ms_median=%7.2f p95=%7.2f geometries=%s" % (
          who(r), r["n"], r["frame_ms_median"], r["frame_ms_p95"], "%.1f" % g if g is not None else "-"))
print()
for n in sorted({r["n"] for r in runs}):
    per = {}
    for r in runs:
        if r["n"] == n: per.setdefault(who(r), []).append(r)
    who_sg = "sgkit"
    sg = [r["frame_ms_median"] for r in per[who_sg]]
    p95 = lambda k: statistics.median(r["frame_ms_p95"] for r in per[k])
    line = [f"n={n}: sgkit {statistics.median(sg):.1f} ms (p95 {p95(who_sg):.1f})"]
    for k in sorted(per):
        if k == "sgkit": continue
        if k.startswith("sgkit"):
            o = [r["frame_ms_median"] for r in per[k]]
            gain = [s / x for s, x in zip(sg, o)]
            line.append(f"{k} {statistics.median(o):.1f} ms (p95 {p95(k):.1f}), "
                        f"gain over sgkit single per round {[round(x, 2) for x in gain]}, median {statistics.median(gain):.2f}x")
            continue
        o = [r["frame_ms_median"] for r in per[k]]
        ratios = [s / x for s, x in zip(sg, o)]
        line.append(f"{k} {statistics.median(o):.1f} ms (p95 {p95(k):.1f}), "
                    f"sgkit/OSG per round {[round(x, 2) for x in ratios]}, median {statistics.median(ratios):.2f}x")
        if k == "openscenegraph draw" and "openscenegraph single" in per:
            osgs = [r["frame_ms_median"] for r in per["openscenegraph single"]]
            gain = [s / x for s, x in zip(osgs, o)]
            line.append(f"  OSG DrawThreadPerContext gain over OSG SingleThreaded per round "
                        f"{[round(x, 2) for x in gain]}, median {statistics.median(gain):.2f}x")
    print("\n  ".join(line))
' <<<"$out"
