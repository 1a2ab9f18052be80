# sgbench pareto: frame time against error, one colour per scene, each scene's Pareto front joined.
if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
  set terminal pngcairo size 960,600 font ',9'
} else {
  set terminal png size 960,600
}
set output './pareto.png'
set logscale x
set logscale y
set grid
set key outside right top
set autoscale fix
set offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05
set xlabel 'differing pixels per view + 1 (against the unculled full-detail render)'
set ylabel 'frame ms over the frame ms of none (medians)'
$all0 << EOD
3031.650 1.00000 "none"
3031.650 0.97340 "aabb"
3031.650 0.79063 "occlusion-tree"
3031.650 0.77046 "hom"
3992.750 0.87066 "gpu-query"
3031.650 0.80865 "default"
EOD
$front0 << EOD
3031.650 0.77046 "hom"
EOD
$default << EOD
3031.650 0.80865
EOD
plot $all0 using 1:2 with points pt 7 ps 1.2 lc 1 title 'factory', \
     $front0 using 1:2 with lines lc 1 notitle, \
     $front0 using 1:2:3 with labels offset 1,0.5 left font ',7' tc lt 1 notitle, \
     $default using 1:2 with points pt 6 ps 2.4 lc rgb 'black' title 'default (CullSettings{})'
