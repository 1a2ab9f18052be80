#!/usr/bin/env bash
# The plot of a `sgbench tiles --baseline --csv FILE` flight: each frame's time and the pixels where the tiles'
# frame differs from the city held in memory (0 once settled), and the frames that were settled.
# usage: bench/tiles_plot.sh FLIGHT.csv OUT.png
set -euo pipefail
csv="${1:?usage: tiles_plot.sh FLIGHT.csv OUT.png}"
out="${2:?usage: tiles_plot.sh FLIGHT.csv OUT.png}"
gnuplot <<GP
set terminal pngcairo size 1000,420 font ",10"
set output "$out"
set datafile separator ","
set key top left
set xlabel "frame"
set ylabel "frame ms"
set y2label "differing pixels (thousands)"
set ytics nomirror
set y2tics
set yrange [0:*]
set y2range [0:*]
plot "$csv" using 1:2 every ::1 with lines lw 1 lc rgb "#3060c0" title "frame ms", \
     "$csv" using 1:(\$9/1000) every ::1 axes x1y2 with lines lw 1 lc rgb "#d04020" title "differing pixels (k)", \
     "$csv" using 1:(\$10 > 0 ? 0 : 1/0) every ::1 with points pt 7 ps 0.3 lc rgb "#20a040" title "settled (0 differing)"
GP
