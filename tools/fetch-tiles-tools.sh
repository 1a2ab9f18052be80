#!/usr/bin/env bash
# CesiumGS' 3d-tiles-tools, Khronos' glTF validator, gltfpack and CesiumGS' gltf-pipeline from the npm registry into
# PREFIX (node_modules): the tile format, tileset and glTF conformance tests check what sgkit reads and writes against
# them; the glTF tests read what gltfpack packs (quantized, meshopt-compressed) and what gltf-pipeline's Draco
# compression makes; three.js poses animated files as an independent reference for the animation player. About 4
# minutes and 230 MB on a cold npm cache.
set -euo pipefail
prefix="${1:?usage: fetch-tiles-tools.sh PREFIX}"
[ -x "$prefix/node_modules/.bin/3d-tiles-tools" ] && [ -d "$prefix/node_modules/gltf-validator" ] &&
  [ -x "$prefix/node_modules/.bin/gltfpack" ] && [ -d "$prefix/node_modules/gltf-pipeline" ] &&
  [ -d "$prefix/node_modules/three" ] && exit 0
npm install --prefix "$prefix" --no-audit --no-fund 3d-tiles-tools@0.5.4 gltf-validator@2.0.0-dev.3.10 gltfpack@1.3.0 \
  gltf-pipeline@4.3.1 three@0.187.0
