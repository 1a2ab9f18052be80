#!/usr/bin/env bash
# CesiumGS' 3d-tiles-tools, Khronos' glTF validator and gltfpack from the npm registry into PREFIX (node_modules):
# the tile format and tileset tests check what sgkit reads and writes against them, the glTF tests read what
# gltfpack packs (quantized, meshopt-compressed). About 4 minutes and 225 MB on a cold npm cache.
set -euo pipefail
prefix="${1:?usage: fetch-tiles-tools.sh PREFIX}"
[ -x "$prefix/node_modules/.bin/3d-tiles-tools" ] && [ -d "$prefix/node_modules/gltf-validator" ] &&
  [ -x "$prefix/node_modules/.bin/gltfpack" ] && exit 0
npm install --prefix "$prefix" --no-audit --no-fund 3d-tiles-tools@0.5.4 gltf-validator@2.0.0-dev.3.10 gltfpack@1.3.0
