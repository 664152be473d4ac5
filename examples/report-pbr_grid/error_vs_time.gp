# Error against run time, written by rayfarm report. Re-draw with: gnuplot THIS_FILE
set terminal pngcairo size 960,640 enhanced font 'DejaVu Sans,10'
set output "error_vs_time.png"
set title "pbr_grid.gltf: error against cycles_lights_studio.png against run time, 640x360, frame 0" noenhanced
set logscale xy
set xlabel 'render time (s, fastest of repeats)'
set ylabel 'RMSE against the reference (8-bit sRGB, 0..1)'
set xrange [0.251548:46.7767]
set yrange [0.0407392:0.177699]
set y2range [0.0407392:0.177699]
set logscale y2
set y2label 'PSNR (dB)'
set ytics nomirror
set y2tics ("20" 0.1, "25" 0.0562341)
set grid xtics ytics mxtics mytics lc rgb '#dddddd'
set key outside right top box opaque noenhanced
set format x '%g'
set format y '%g'
$f_default << EOD
0.554422 0.0738745 "1spp d5 w0.001 i0"
EOD
$f_depth << EOD
0.402477 0.111062 "1spp d1 w0.001 i0"
0.4679 0.0988932 "1spp d2 w0.001 i0"
0.516096 0.0738851 "1spp d3 w0.001 i0"
0.495754 0.0739632 "1spp d4 w0.001 i0"
0.493578 0.073827 "1spp d6 w0.001 i0"
0.587796 0.073807 "1spp d7 w0.001 i0"
0.600636 0.0738185 "1spp d8 w0.001 i0"
EOD
$f_indirect << EOD
2.32566 0.0791751 "1spp d5 w0.001 i1"
3.63492 0.0683263 "1spp d5 w0.001 i4"
11.1167 0.0651827 "1spp d5 w0.001 i16"
EOD
$f_min_weight << EOD
0.609046 0.0738604 "1spp d5 w0 i0"
0.622785 0.0742952 "1spp d5 w0.01 i0"
0.410698 0.0868393 "1spp d5 w0.1 i0"
EOD
$f_spp << EOD
1.66648 0.0709276 "4spp d5 w0.001 i0"
5.26973 0.0701503 "16spp d5 w0.001 i0"
29.2354 0.0700512 "64spp d5 w0.001 i0"
EOD
$frontlabels << EOD
0.402477 0.111062 "1spp d1 w0.001 i0"
1.66648 0.0709276 "4spp d5 w0.001 i0"
3.63492 0.0683263 "1spp d5 w0.001 i4"
11.1167 0.0651827 "1spp d5 w0.001 i16"
EOD
$front << EOD
0.402477 0.111062 "1spp d1 w0.001 i0"
0.410698 0.0868393 "1spp d5 w0.1 i0"
0.493578 0.073827 "1spp d6 w0.001 i0"
0.587796 0.073807 "1spp d7 w0.001 i0"
1.66648 0.0709276 "4spp d5 w0.001 i0"
3.63492 0.0683263 "1spp d5 w0.001 i4"
11.1167 0.0651827 "1spp d5 w0.001 i16"
EOD
$default << EOD
0.554422 0.0738745 "1spp d5 w0.001 i0"
EOD
plot $f_default using 1:2 with points pt 5 ps 1.3 title "sweep: default", \
     $f_depth using 1:2 with points pt 6 ps 1.3 title "sweep: depth", \
     $f_indirect using 1:2 with points pt 7 ps 1.3 title "sweep: indirect", \
     $f_min_weight using 1:2 with points pt 8 ps 1.3 title "sweep: min_weight", \
     $f_spp using 1:2 with points pt 9 ps 1.3 title "sweep: spp", \
     $front using 1:2 with linespoints lw 2 lc rgb '#d62728' pt 7 ps 0.8 title 'Pareto front', \
     $frontlabels using 1:2:3 with labels offset 0.8,0.8 left font ',8' tc rgb '#d62728' notitle, \
     $default using 1:2 with points pt 6 ps 3.5 lw 2 lc rgb 'black' title 'default setting'
