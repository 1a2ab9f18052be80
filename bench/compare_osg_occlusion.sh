#!/usr/bin/env bash
# Occlusion culling, sgkit against OpenSceneGraph, on city's street path: runs the OpenSceneGraph peer with
# --occlusion --with-sgkit (both toolkits culled alternately on every frame in one process, so that both
# see the same machine speed) ROUNDS times for each OpenSceneGraph occluder configuration, prints each run
# and the medians over the rounds of the per-frame time ratios and of the triangle ratios.
#   bench/compare_osg_occlusion.sh BUILD_DIR [N]     (BUILD_DIR configured with -DSGKIT_BENCH_OSG=ON)
# Environment: ROUNDS (default 3); OSG_CONFIGS, a ';'-separated list of extra peer arguments, one entry per
# OpenSceneGraph configuration (default: the box's side faces, its diagonal cross-sections (the peer's
# default), and the diagonals range-limited to 120 m; see bench/osg_peer/sgbench_osg.cpp).
set -euo pipefail
build=${1:?build directory}
n=${2:-100}
rounds=${ROUNDS:-3}
configs=${OSG_CONFIGS:-"--osg-occluders sides;--osg-occluders diagonals;--osg-occluders diagonals --osg-occluder-range 120"}
peer="$build/bench/osg_peer/sgbench_osg"
IFS=';' read -r -a cfgs <<< "$configs"
read -r -d '' summary <<'PY' || true
import json, statistics, sys
runs = [json.loads(l) for l in sys.stdin if l.startswith("{")]
if not runs or "sgkit_cull_ms_median" not in runs[0]:
    sys.exit("no sgkit fields: is the peer built inside the sgkit project?")
def cfg(r):
    s = "%s, max %d active" % (r["osg_occluders"], r["osg_max_active_occluders"])
    s += ", range %g m" % r["osg_occluder_range"] if r["osg_occluder_range"] > 0 else ", no range"
    return s
print("%-36s %9s %9s %9s %9s %9s | %9s %9s %9s %9s" % ("OpenSceneGraph occluders", "osg_off", "osg_occ", "collect",
      "tris_off", "tris_occ", "sg_off", "sg_occ", "sg_t_off", "sg_t_occ"))
for r in runs:
    print("%-36s %9.3f %9.3f %9.3f %9.0f %9.0f | %9.3f %9.3f %9.0f %9.0f" % (cfg(r),
          r["cull_ms_median_no_occlusion"], r["cull_ms_median"], r["occluder_collect_ms_median"],
          r["triangles_mean_no_occlusion"], r["triangles_mean"],
          r["sgkit_cull_ms_median_no_occlusion"], r["sgkit_cull_ms_median"],
          r["sgkit_triangles_mean_no_occlusion"], r["sgkit_triangles_mean"]))
print()
med = statistics.median
for c in dict.fromkeys(cfg(r) for r in runs):
    rs = [r for r in runs if cfg(r) == c]
    def m(k): return med(r[k] for r in rs)
    print(f"OpenSceneGraph occluders: {c} ({len(rs)} runs; medians over runs of per-frame medians)")
    print(f"  OSG   occlusion/frustum cull time {m('occlusion_over_frustum_cull_per_frame_median'):.2f}x, "
          f"triangles {m('occlusion_over_frustum_triangles'):.3f} "
          f"({m('triangles_mean'):.0f} of {m('triangles_mean_no_occlusion'):.0f}), "
          f"{m('active_occluders_mean'):.1f} active occluders")
    print(f"  sgkit occlusion/frustum cull time {m('sgkit_occlusion_over_frustum_cull_per_frame_median'):.2f}x, "
          f"triangles {m('sgkit_occlusion_over_frustum_triangles'):.3f} "
          f"({m('sgkit_triangles_mean'):.0f} of {m('sgkit_triangles_mean_no_occlusion'):.0f}), "
          f"{m('sgkit_occluders_used_mean'):.1f} occluders used")
    print(f"  OSG/sgkit cull time: frustum only {m('osg_over_sgkit_per_frame_median_no_occlusion'):.1f}x, "
          f"with occlusion {m('osg_over_sgkit_per_frame_median'):.1f}x; "
          f"OSG/sgkit triangles with occlusion {m('osg_over_sgkit_triangles'):.3f}")
    bad = sum(r["occlusion_leaves_not_in_frustum_set"] for r in rs)
    if bad:
        print(f"  WARNING: {bad} OSG occlusion draw leaves were not in its frustum-only set")
PY
for r in $(seq "$rounds"); do
  for c in "${cfgs[@]}"; do
    # shellcheck disable=SC2086
    "$peer" --occlusion --n "$n" --path street --with-sgkit --json $c
  done
done | python3 -c "$summary"
