#!/usr/bin/env bash
# The tiles' loads from disk and over the network, on 127.0.0.1: `sgbench tiles --path teleport` with 1, 2 and 4
# loader threads from disk, from Debian's nginx over HTTP/1.1 and over HTTP/2 with TLS (bench/serve-nginx.sh; a
# certificate of the script's own authority), interleaved round by round so that the machine's drift falls on all
# alike. Then the disk cache: the same teleport flown twice over HTTP/2 against a server whose responses may be kept
# an hour, with one cache file; the server's access log counts the second flight's requests. JSON lines on stdout,
# each with "source", "loaders" and "round" added.
#   bench/tiles_http.sh BUILD TILES_DIR N [ROUNDS]     e.g. bench/tiles_http.sh build/release tiles256 256 2
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 BUILD TILES_DIR N [ROUNDS]" >&2; exit 2; }
build=$1 tiles=$(realpath "$2") n=$3 rounds=${4:-1}
here=$(dirname "$(realpath "$0")")
sgbench="$build/bench/sgbench"
work=$(mktemp -d "${TMPDIR:-/tmp}/sgkit-tiles-http-XXXXXX")
pids=()
cleanup() { for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 -subj /CN=127.0.0.1 \
  -addext subjectAltName=IP:127.0.0.1 -keyout "$work/key.pem" -out "$work/cert.pem" 2>/dev/null

# serve NAME [serve-nginx.sh options]: starts a server; URL[NAME] and LOG[NAME] say where it is and what it logs.
declare -A URL LOG
serve() {
  local name=$1; shift
  "$here/serve-nginx.sh" "$tiles" "$@" >"$work/$name.url" 2>"$work/$name.err" </dev/null &
  pids+=("$!")
  until [ -s "$work/$name.url" ]; do
    kill -0 "$!" 2>/dev/null || { cat "$work/$name.err" >&2; exit 1; }
    sleep 0.1
  done
  URL[$name]=$(head -1 "$work/$name.url")
  LOG[$name]=$(sed -n 's/.*access log \(.*\)$/\1/p' "$work/$name.err")
}
serve h1
serve h2 --tls "$work/cert.pem" "$work/key.pem"

run() {  # run SOURCE LOADERS ROUND TILESET [sgbench options]
  local source=$1 loaders=$2 round=$3 tileset=$4; shift 4
  "$sgbench" tiles --tileset "$tileset" --n "$n" --path teleport --loaders "$loaders" --json "$@" |
    sed "s/^{/{\"source\": \"$source\", \"round\": $round, /"
}
for ((r = 1; r <= rounds; r++)); do
  for k in 1 2 4; do
    run disk "$k" "$r" "$tiles/tileset.json"
    run http1.1 "$k" "$r" "${URL[h1]}/tileset.json"
    run http2+tls "$k" "$r" "${URL[h2]}/tileset.json" --ca-file "$work/cert.pem"
  done
done

# The cache: a server whose responses may be kept an hour, two flights with one cache file.
serve cached --tls "$work/cert.pem" "$work/key.pem" --max-age 3600
for flight in 1 2; do
  before=$(wc -l <"${LOG[cached]}")
  line=$(run "cache flight $flight" 2 1 "${URL[cached]}/tileset.json" --ca-file "$work/cert.pem" \
    --cache "$work/cache.sqlite")
  echo "${line%\}}, \"server_requests\": $(($(wc -l <"${LOG[cached]}") - before))}"
done
