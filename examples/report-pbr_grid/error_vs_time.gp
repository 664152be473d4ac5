# Error against run time, written by rayfarm report. Re-draw with: gnuplot THIS_FILE
set terminal pngcairo size 960,640 enhanced font 'DejaVu Sans,10'
set output "error_vs_time.png"
set title "pbr_grid.gltf: error against cycles_lights_studio.png against run time, 640x360, frame 0" noenhanced
set logscale xy
set xlabel 'render time (s, fastest of repeats)'
set ylabel 'RMSE against the reference (8-bit sRGB, 0..1)'
set xrange [0.498369:80.1287]
set yrange [0.043782:0.178299]
set y2range [0.043782:0.178299]
set logscale y2
set y2label 'PSNR (dB)'
set ytics nomirror
set y2tics ("15" 0.177828, "20" 0.1, "25" 0.0562341)
set grid xtics ytics mxtics mytics lc rgb '#dddddd'
set key outside right top box opaque noenhanced
set format x '%g'
set format y '%g'
$f_default << EOD
1.05238 0.0744396 "1spp d5 w0.001"
EOD
$f_depth << EOD
0.797391 0.111437 "1spp d1 w0.001"
1.29008 0.0993222 "1spp d2 w0.001"
1.09717 0.0744501 "1spp d3 w0.001"
1.36955 0.0745276 "1spp d4 w0.001"
0.943856 0.0743925 "1spp d6 w0.001"
1.27861 0.0743727 "1spp d7 w0.001"
1.20798 0.074384 "1spp d8 w0.001"
EOD
$f_min_weight << EOD
1.05668 0.0744255 "1spp d5 w0"
0.823344 0.0748589 "1spp d5 w0.01"
1.11624 0.0873518 "1spp d5 w0.1"
EOD
$f_spp << EOD
3.23231 0.0709672 "4spp d5 w0.001"
9.73538 0.0701513 "16spp d5 w0.001"
50.0805 0.0700511 "64spp d5 w0.001"
EOD
$frontlabels << EOD
0.797391 0.111437 "1spp d1 w0.001"
1.27861 0.0743727 "1spp d7 w0.001"
3.23231 0.0709672 "4spp d5 w0.001"
9.73538 0.0701513 "16spp d5 w0.001"
50.0805 0.0700511 "64spp d5 w0.001"
EOD
$front << EOD
0.797391 0.111437 "1spp d1 w0.001"
0.823344 0.0748589 "1spp d5 w0.01"
0.943856 0.0743925 "1spp d6 w0.001"
1.20798 0.074384 "1spp d8 w0.001"
1.27861 0.0743727 "1spp d7 w0.001"
3.23231 0.0709672 "4spp d5 w0.001"
9.73538 0.0701513 "16spp d5 w0.001"
50.0805 0.0700511 "64spp d5 w0.001"
EOD
$default << EOD
1.05238 0.0744396 "1spp d5 w0.001"
EOD
plot $f_default using 1:2 with points pt 5 ps 1.3 title "sweep: default", \
     $f_depth using 1:2 with points pt 6 ps 1.3 title "sweep: depth", \
     $f_min_weight using 1:2 with points pt 7 ps 1.3 title "sweep: min_weight", \
     $f_spp using 1:2 with points pt 8 ps 1.3 title "sweep: spp", \
     $front using 1:2 with linespoints lw 2 lc rgb '#d62728' pt 7 ps 0.8 title 'Pareto front', \
     $frontlabels using 1:2:3 with labels offset 0.8,0.8 left font ',8' tc rgb '#d62728' notitle, \
     $default using 1:2 with points pt 6 ps 3.5 lw 2 lc rgb 'black' title 'default setting'
