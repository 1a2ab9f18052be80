#!/usr/bin/env bash
# Generated occluders against authored ones (docs/benchmarks.md, "Generated occluders"): the city street path, the
# office walk, the factory path, a city saved by sgview --save and the city written as tiles by sgtile (occluders made
# in each tile as it is read; the built city's authored boxes beside the tiles for the yardstick), each with its
# authored occluders and with occluders made from its geometry instead, alternating (A B A B ...) so that both see the
# same machine speed. Triangles drawn
# and pixels differing from the unculled render come from the first round (they do not vary); times are medians of
# the rounds' medians.
#   bench/generated_occluders.sh BUILD_DIR
set -euo pipefail
build=${1:?build directory}
rounds=${ROUNDS:-3}
sgbench="$build/bench/sgbench"
glb=$(mktemp --suffix=.glb)
tiles=$(mktemp -d)
trap 'rm -rf "$glb" "$tiles"' EXIT
"$build/examples/sgview" --scene city --n 100 --save "$glb" >/dev/null
"$build/examples/sgtile" --city 100 --out "$tiles" >/dev/null
{
  for r in $(seq "$rounds"); do
    px=""
    [ "$r" = 1 ] && px="--pixels"
    for o in authored generated; do
      "$sgbench" occlusion --scene city --n 100 --path street --occluders "$o" $px --json
      "$sgbench" occlusion --scene office --r 8 --path walk --occluders "$o" $px --json
      "$sgbench" occlusion --scene factory --occluders "$o" $px --json
    done
    "$sgbench" occlusion --scene city --n 100 --path street --gltf "$glb" --occluders generated $px --json
    for o in authored generated; do
      "$sgbench" occlusion --scene city --n 100 --path street --tileset "$tiles/tileset.json" --occluders "$o" $px --json
    done
  done
} | python3 -c '
import json, statistics, sys
runs = [json.loads(l) for l in sys.stdin if l.startswith("{")]
def key(r): return (r["scene"], "gltf" if "gltf" in r else ("tiles-" + r["occluders"]) if "tileset" in r else r["occluders"])
groups = {}
for r in runs: groups.setdefault(key(r), []).append(r)
print("| scene | occluders | made (boxes, polygons) | ms to make (per million distinct / scene triangles) | triangles drawn (mean per frame) | over authored | differing pixels (frames with any) | pass ms (median) | over authored (same round) | frame ms (median) |")
print("|---|---|---|---|---|---|---|---|---|---|")
for scene in ("city", "office", "factory"):
    for kind in ("authored", "generated", "gltf", "tiles-authored", "tiles-generated"):
        # The tiles against the authored boxes of the built city, placed beside the same tiles.
        a = groups.get((scene, "tiles-authored" if kind.startswith("tiles") else "authored"))
        rs = groups.get((scene, kind))
        if not rs: continue
        first = next((r for r in rs if "differing_pixels_total" in r), rs[0])
        tris = first["triangles_occlusion_mean"]
        pass_ms = statistics.median(r["occlusion_ms_median"] for r in rs)
        frame_ms = statistics.median(r["frame_ms_median_occlusion"] for r in rs)
        made = gen = "-"
        if "authored" not in kind:
            made = "%d, %d" % (first["generated_boxes"], first["generated_polygons"])
            gen = "%.1f (%.0f / %.1f)" % (statistics.median(r["generate_ms"] for r in rs),
                  statistics.median(r["ms_per_million_mesh_triangles"] for r in rs),
                  statistics.median(r["ms_per_million_scene_triangles"] for r in rs))
        ta = a[0]["triangles_occlusion_mean"] if a else float("nan")
        # The pass time over the authored run of the same round (both ran back to back), median over rounds.
        pa = statistics.median(g["occlusion_ms_median"] / x["occlusion_ms_median"] for x, g in zip(a, rs)) if a else float("nan")
        label = {"gltf": "generated, read from glTF", "tiles-authored": "authored, beside tiles (sgtile)",
                 "tiles-generated": "generated in tiles (sgtile)"}.get(kind, kind)
        print("| %s | %s | %s | %s | %.0f | %.3f | %s (%s) | %.3f | %.2f | %.1f |" % (scene, label, made, gen, tris,
              tris / ta, int(first.get("differing_pixels_total", -1)), int(first.get("views_with_error", -1)),
              pass_ms, pa, frame_ms))
'
