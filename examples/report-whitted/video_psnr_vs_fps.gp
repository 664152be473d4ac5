# Encoded MP4 against the lossless frames, written by rayfarm report. Re-draw: gnuplot THIS_FILE
set terminal pngcairo size 960,640 enhanced font 'DejaVu Sans,10'
set output "video_psnr_vs_fps.png"
set title "encoded MP4 against lossless frames, 24 frames 320x180" noenhanced
set logscale x
set xlabel 'encoding speed (frames/s, open to close of the MP4 sink)'
set ylabel 'PSNR against the lossless frames (dB)'
set grid lc rgb '#dddddd'
set key outside right top box opaque noenhanced
set format x '%g'
set xtics (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000)
set xrange [24.5476:1474.32]
set yrange [19.04:43.7566]
$p_medium << EOD
107.528 41.7566 "crf 0"
59.4721 37.9091 "crf 12"
56.2934 34.6435 "crf 18"
79.5603 30.6322 "crf 23"
88.727 26.0037 "crf 28"
118.492 21.1233 "crf 35"
EOD
$p_slow << EOD
74.9925 41.7566 "crf 0"
36.8214 37.9937 "crf 12"
37.9324 34.6727 "crf 18"
41.9797 30.6636 "crf 23"
68.8707 25.9804 "crf 28"
77.8445 21.04 "crf 35"
EOD
$p_ultrafast << EOD
480.11 41.7566 "crf 0"
496.831 37.6849 "crf 12"
547.177 33.872 "crf 18"
791.096 30.0008 "crf 23"
827.52 25.9639 "crf 28"
982.877 21.4005 "crf 35"
EOD
$p_veryfast << EOD
215.016 41.7566 "crf 0"
180.134 36.9033 "crf 12"
194.55 33.0501 "crf 18"
202.415 29.2865 "crf 23"
213.698 25.5032 "crf 28"
283.235 21.0663 "crf 35"
EOD
$front << EOD
480.11 41.7566
496.831 37.6849
547.177 33.872
791.096 30.0008
827.52 25.9639
982.877 21.4005
EOD
plot $p_medium using 1:2 with linespoints pt 5 ps 1.3 title "preset medium", \
     $p_medium using 1:2:3 with labels offset 0.9,0 left font ',8' notitle, \
     $p_slow using 1:2 with linespoints pt 6 ps 1.3 title "preset slow", \
     $p_slow using 1:2:3 with labels offset 0.9,0 left font ',8' notitle, \
     $p_ultrafast using 1:2 with linespoints pt 7 ps 1.3 title "preset ultrafast", \
     $p_ultrafast using 1:2:3 with labels offset 0.9,0 left font ',8' notitle, \
     $p_veryfast using 1:2 with linespoints pt 8 ps 1.3 title "preset veryfast", \
     $p_veryfast using 1:2:3 with labels offset 0.9,0 left font ',8' notitle, \
     $front using 1:2 with lines lw 3 lc rgb '#d62728' dt 2 title 'Pareto front'
