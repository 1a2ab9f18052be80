#!/usr/bin/env bash
# The occlusion methods side by side: the occlusion tree, the occlusion map (conservative and approximate), the
# PVS alone and before each, on city N=100's street path, office R=8's walk and the factory's walkthrough (the
# PVS: city and office), 240 frames each at 1280x720, every frame also drawn unculled to count differing pixels.
# Per run the frames alternate frustum culling alone and the method, so that both see the same machine speed.
#   bench/occlusion_methods.sh BUILD_DIR [--every K]
set -euo pipefail
build=${1:?build directory}
shift
sgbench="$build/bench/sgbench"
{
  for scene in "city --n 100 --path street" "office --r 8 --path walk" "factory"; do
    # shellcheck disable=SC2086
    "$sgbench" occlusion --scene $scene --method tree --ideal --json "$@"
    for m in hom hom-approx pvs pvs+tree pvs+hom; do
      case "$scene:$m" in factory:pvs*) continue ;; esac
      # shellcheck disable=SC2086
      "$sgbench" occlusion --scene $scene --method "$m" --pixels --json "$@"
    done
    # shellcheck disable=SC2086
    "$sgbench" occlusion --scene $scene --method tree --pixels --json "$@"
  done
} | python3 -c '
import json, sys
runs = [json.loads(l) for l in sys.stdin if l.startswith("{")]
ideal = {r["scene"]: r["triangles_visible_mean"] for r in runs if "triangles_visible_mean" in r}
print("| scene | method | triangles drawn (of frustum) | over the exact visible set | pass ms (median) | cull ms (median) | frame ms frustum / method (median) | frame speed-up | differing pixels (views) | PVS build s |")
print("|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    if "differing_pixels_total" not in r: continue
    pvs = "%.1f" % (r["pvs_build_ms"] / 1000) if "pvs_build_ms" in r else ""
    print("| %s | %s | %.0f (%.3f) | %.2fx | %.3f | %.3f | %.1f / %.1f | %.2fx | %.0f (%d) | %s |" % (
        r["scene"], r["method"], r["triangles_occlusion_mean"], r["occlusion_over_frustum"],
        r["triangles_occlusion_mean"] / ideal[r["scene"]], r["occlusion_ms_median"], r["cull_ms_median_occlusion"],
        r["frame_ms_median_frustum"], r["frame_ms_median_occlusion"], r["frame_speedup_median"],
        r["differing_pixels_total"], r["views_with_error"], pvs))
print()
for s, v in ideal.items(): print("exact visible set, %s: %.0f triangles" % (s, v))
'
