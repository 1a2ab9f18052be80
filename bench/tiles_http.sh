#!/usr/bin/env bash
# The tiles' loads from disk and over the network, on 127.0.0.1: `sgbench tiles --path teleport` with 1, 2 and 4
# loader threads from disk, from Debian's nginx over HTTP/1.1 and over HTTP/2 with TLS (bench/serve-nginx.sh; a
# certificate of the script's own authority), interleaved round by round so that the machine's drift falls on all
# alike. The server sends each file gzipped as a CDN does, compressed once (FILE.gz beside it, made here when
# missing: nginx's gzip_static), so that compressing for every request does not take the loaders' cores; one more
# run per loader count compresses on the fly, as a plain nginx would. Then the disk cache: the same teleport flown twice over HTTP/2 against a server whose responses may be kept
# an hour, with one cache file; the server's access log counts the second flight's requests. JSON lines on stdout,
# each with "source", "loaders" and "round" added.
#   bench/tiles_http.sh BUILD TILES_DIR N [ROUNDS]     e.g. bench/tiles_http.sh build/release tiles256 256 2
# SECTIONS="teleport loads cache" (the default) picks the parts run.
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
find "$tiles" -type f ! -name '*.gz' -print0 | while IFS= read -r -d '' f; do
  [ -e "$f.gz" ] || echo "$f"
done | xargs -r -P 2 -n 64 gzip -k -6
serve h1 --gzip-static
serve h2 --tls "$work/cert.pem" "$work/key.pem" --gzip-static
serve fly

run() {  # run SOURCE LOADERS ROUND TILESET [sgbench options]
  local source=$1 loaders=$2 round=$3 tileset=$4; shift 4
  "$sgbench" tiles --tileset "$tileset" --n "$n" --path teleport --loaders "$loaders" --json "$@" |
    sed "s/^{/{\"source\": \"$source\", \"round\": $round, /"
}
sections=${SECTIONS:-teleport loads cache}
[[ $sections == *teleport* ]] || rounds_teleport=0
for ((r = 1; r <= ${rounds_teleport:-$rounds}; r++)); do
  for k in 1 2 4; do
    run disk "$k" "$r" "$tiles/tileset.json"
    run http1.1 "$k" "$r" "${URL[h1]}/tileset.json"
    run http2+tls "$k" "$r" "${URL[h2]}/tileset.json" --ca-file "$work/cert.pem"
    [ "$r" -gt 1 ] || run "http1.1, gzip on the fly" "$k" "$r" "${URL[fly]}/tileset.json"
  done
done

# The load function alone, one tile after another on one thread (`--path loads`): what the network adds to a load,
# per MB of content, without the frames' share of the cores.
[[ $sections == *loads* ]] || rounds_loads=0
for ((r = 1; r <= ${rounds_loads:-$rounds}; r++)); do
  for source in disk http1.1 http2+tls; do
    case $source in
      disk) set -- "$tiles/tileset.json" ;;
      http1.1) set -- "${URL[h1]}/tileset.json" ;;
      *) set -- "${URL[h2]}/tileset.json" --ca-file "$work/cert.pem" ;;
    esac
    "$sgbench" tiles --tileset "$1" "${@:2}" --path loads --loads 100 --runs 1 --parse-dir "$tiles" --json |
      sed "s/^{/{\"source\": \"$source\", \"round\": $r, /"
  done
done

# The cache: a server whose responses may be kept an hour, two flights with one cache file.
# "server_requests_again": requests of the second flight for a URI the first already had (fresh in the cache).
[[ $sections == *cache* ]] || exit 0
serve cached --tls "$work/cert.pem" "$work/key.pem" --max-age 3600 --gzip-static
for flight in 1 2; do
  before=$(wc -l <"${LOG[cached]}")
  line=$(run "cache flight $flight" 2 1 "${URL[cached]}/tileset.json" --ca-file "$work/cert.pem" \
    --cache "$work/cache.sqlite")
  tail -n +"$((before + 1))" "${LOG[cached]}" | cut -f2 | sort -u >"$work/flight$flight.uris"
  again=0
  [ "$flight" = 1 ] || again=$(comm -12 "$work/flight1.uris" "$work/flight2.uris" | wc -l)
  echo "${line%\}}, \"server_requests\": $(($(wc -l <"${LOG[cached]}") - before)), \"server_requests_again\": $again}"
done
