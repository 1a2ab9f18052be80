#!/usr/bin/env bash
# The map's memory: resident memory with the world, the United States and one state (Texas) loaded, against the
# loaded levels' geometry plus the program without a map (and plus the program once it has drawn two boxes, which
# compiles its shaders); then 100 enter/back cycles over random states (fixed
# seed) and the resident memory after the first cycle and after the last. Also the frame rate at the world and
# U.S. levels (1280x720) and the time to enter Texas.
#   bench/map/map_memory.sh BUILD_DIR [DATA_DIR [SGMAP_OPTION...]]   (DATA_DIR: BUILD_DIR/mapdata/levels;
#   e.g. --loader-nice 10)
set -euo pipefail
build=${1:?usage: map_memory.sh BUILD_DIR [DATA_DIR [SGMAP_OPTION...]]}
data=${2:-$build/mapdata/levels}
shift $(( $# < 2 ? $# : 2 ))
states="01 02 04 05 06 08 09 10 11 12 13 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32 33 34 35 36 37 38 39 40 41 42 44 45 46 47 48 49 50 51 53 54 55 56 72"
script=$(mktemp)
trap 'rm -f "$script"' EXIT
{
  echo "frames 60"
  echo "stats"
  echo "enter 840"
  echo "frames 60"
  echo "stats"
  echo "enter 48"
  echo "frames 30"
  echo "stats"
  echo "back"
  echo "$states" | awk 'BEGIN { srand(1) } { n = split($0, s, " "); for (i = 1; i <= 100; i++) {
      print "enter " s[int(rand() * n) + 1]; print "back"; if (i == 1) print "stats"; } }'
  echo "frames 10"
  echo "stats"
} > "$script"
"$build/examples/sgmap" --headless --data "$data" --script "$script" "$@" | awk -F'\t' '
  /^level/ { n++; for (i = 1; i <= NF; i++) { split($i, kv, " "); v[n, kv[1]] = kv[2] } }
  !texas && /^state\t48\t/ { texas = $4 " " $5 " " $6; after = 1; next }
  /^frames/ && after { texasFrames = $3; after = 0 }
  END {
    printf "world level: %.1f fps\n", v[1, "fps"]
    printf "U.S. level: %.1f fps\n", v[2, "fps"]
    printf "entering Texas: %s; then at the same view: %s\n", texas, texasFrames
    g = v[3, "geometry_kb"]; e = v[3, "empty_kb"]; y = v[3, "ready_kb"]; r = v[3, "rss_kb"]; f = v[3, "rss_file_kb"]
    printf "Texas loaded: resident %.1f MB (%.1f MB of it mapped files); geometry %.1f MB + program without a map %.1f MB = %.1f MB; ratio %.2f\n",
      r / 1024, f / 1024, g / 1024, e / 1024, (g + e) / 1024, r / (g + e)
    if (y > 0)
      printf "  against geometry + the program ready to draw (two boxes drawn, its shaders compiled) %.1f MB = %.1f MB: ratio %.2f\n",
        y / 1024, (g + y) / 1024, r / (g + y)
    printf "after 1 enter/back cycle: %.1f MB; after 100: %.1f MB (%+.1f%%)\n", v[4, "rss_kb"] / 1024,
      v[5, "rss_kb"] / 1024, 100 * (v[5, "rss_kb"] / v[4, "rss_kb"] - 1)
  }'
