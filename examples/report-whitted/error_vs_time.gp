# Error against run time, written by rayfarm report. Re-draw with: gnuplot THIS_FILE
set terminal pngcairo size 960,640 enhanced font 'DejaVu Sans,10'
set output "error_vs_time.png"
set title "whitted.json: error against run time, 320x180, frame 0" noenhanced
set logscale xy
set xlabel 'render time (s, fastest of repeats)'
set ylabel 'RMSE against the reference (8-bit sRGB, 0..1)'
set xrange [0.00431275:1.96499]
set yrange [0.00344152:0.367269]
set y2range [0.00344152:0.367269]
set logscale y2
set y2label 'PSNR (dB)'
set ytics nomirror
set y2tics ("10" 0.316228, "20" 0.1, "30" 0.0316228, "40" 0.01)
set grid xtics ytics mxtics mytics lc rgb '#dddddd'
set key outside right top box opaque noenhanced
set format x '%g'
set format y '%g'
$f_default << EOD
0.0152597 0.0645692 "1spp d5 w0.001"
EOD
$f_depth << EOD
0.0069004 0.229543 "1spp d1 w0.001"
0.0103368 0.142271 "1spp d2 w0.001"
0.0124915 0.0736001 "1spp d3 w0.001"
0.0140552 0.0649779 "1spp d4 w0.001"
0.0155926 0.0644964 "1spp d6 w0.001"
0.0164249 0.0644843 "1spp d7 w0.001"
0.0170592 0.0644831 "1spp d8 w0.001"
EOD
$f_min_weight << EOD
0.020283 0.0645332 "1spp d5 w0"
0.0157973 0.0675815 "1spp d5 w0.01"
0.00788139 0.193605 "1spp d5 w0.1"
EOD
$f_spp << EOD
0.059541 0.0296548 "4spp d5 w0.001"
0.232058 0.0121685 "16spp d5 w0.001"
1.22812 0.00550643 "64spp d5 w0.001"
EOD
$frontlabels << EOD
0.0069004 0.229543 "1spp d1 w0.001"
0.0103368 0.142271 "1spp d2 w0.001"
0.0124915 0.0736001 "1spp d3 w0.001"
0.059541 0.0296548 "4spp d5 w0.001"
0.232058 0.0121685 "16spp d5 w0.001"
1.22812 0.00550643 "64spp d5 w0.001"
EOD
$front << EOD
0.0069004 0.229543 "1spp d1 w0.001"
0.00788139 0.193605 "1spp d5 w0.1"
0.0103368 0.142271 "1spp d2 w0.001"
0.0124915 0.0736001 "1spp d3 w0.001"
0.0140552 0.0649779 "1spp d4 w0.001"
0.0152597 0.0645692 "1spp d5 w0.001"
0.0155926 0.0644964 "1spp d6 w0.001"
0.0164249 0.0644843 "1spp d7 w0.001"
0.0170592 0.0644831 "1spp d8 w0.001"
0.059541 0.0296548 "4spp d5 w0.001"
0.232058 0.0121685 "16spp d5 w0.001"
1.22812 0.00550643 "64spp d5 w0.001"
EOD
$default << EOD
0.0152597 0.0645692 "1spp d5 w0.001"
EOD
plot $f_default using 1:2 with points pt 5 ps 1.3 title "sweep: default", \
     $f_depth using 1:2 with points pt 6 ps 1.3 title "sweep: depth", \
     $f_min_weight using 1:2 with points pt 7 ps 1.3 title "sweep: min_weight", \
     $f_spp using 1:2 with points pt 8 ps 1.3 title "sweep: spp", \
     $front using 1:2 with linespoints lw 2 lc rgb '#d62728' pt 7 ps 0.8 title 'Pareto front', \
     $frontlabels using 1:2:3 with labels offset 0.8,0.8 left font ',8' tc rgb '#d62728' notitle, \
     $default using 1:2 with points pt 6 ps 3.5 lw 2 lc rgb 'black' title 'default setting'
