#!/usr/bin/env bash
# Installs what sgkit needs to build, test and benchmark, from Debian 12 packages (as root, or with sudo).
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config libglm-dev libtinygltf-dev libglfw3-dev libosmesa6-dev
      libgl-dev libegl-dev libmeshoptimizer-dev libstb-dev libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth
      nlohmann-json3-dev libglu1-mesa-dev  # the map converter's TopoJSON reader; GLU's tessellator compared
      libcurl4-openssl-dev  # sg::readResource: tiles and tilesets by URL
      libsqlite3-dev  # the HTTP disk cache (sg::HttpCache)
      libdraco-dev  # glTF's KHR_draco_mesh_compression
      assimp-testmodels  # glTF files written elsewhere: the loader's conformance test
      python3 openssl  # the tests' local HTTP and HTTPS server (tests/loaders/net/tile_server.py), its certificate
      nginx  # the web server tiles are served with, run by the tests on ports of their own (tests/loaders/net/Nginx.h):
             # Debian 12's nginx has the ssl, http_v2 and gzip modules (nginx-light only adds an echo module)
      ca-certificates  # the system's certificate authorities, which https reads trust without a CA file
      clang-14 libclang-rt-14-dev  # clang: the glTF loader's libFuzzer target
      clang-format  # the format check of .ci/run
      gnuplot-nox)  # sgbench pareto's plot (pngcairo)
[ "${SGKIT_BENCH_OSG:-0}" = 1 ] && pkgs+=(libopenscenegraph-dev)
missing=()
for p in "${pkgs[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo=""; [ "$(id -u)" = 0 ] || sudo=sudo
export DEBIAN_FRONTEND=noninteractive
# Services the packages bring (nginx's, on port 80) are not started: the tests run their own, and in a container
# without an init system the start can fail the install. A policy-rc.d that forbids starts, for this install only
# (Docker images have one already).
policy=/usr/sbin/policy-rc.d
if [ ! -e "$policy" ]; then
  printf '#!/bin/sh\nexit 101\n' | $sudo tee "$policy" >/dev/null
  $sudo chmod 755 "$policy"
  trap '$sudo rm -f "$policy"' EXIT
fi
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
