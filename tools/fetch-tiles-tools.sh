#!/usr/bin/env bash
# CesiumGS' 3d-tiles-tools from the npm registry into PREFIX (node_modules/.bin/3d-tiles-tools): the tile format and
# tileset tests check against it. About 4 minutes and 225 MB on a cold npm cache.
set -euo pipefail
prefix="${1:?usage: fetch-tiles-tools.sh PREFIX}"
[ -x "$prefix/node_modules/.bin/3d-tiles-tools" ] && exit 0
npm install --prefix "$prefix" --no-audit --no-fund 3d-tiles-tools@0.5.4
