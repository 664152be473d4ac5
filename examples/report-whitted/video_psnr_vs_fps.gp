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
set xrange [30.7022:1848.96]
set yrange [19.0424:43.7574]
$p_medium << EOD
133.574 41.7574 "crf 0"
107.353 37.9008 "crf 12"
111.325 34.6483 "crf 18"
120.117 30.6053 "crf 23"
130.668 26.0143 "crf 28"
174.498 21.131 "crf 35"
EOD
$p_slow << EOD
109.55 41.7574 "crf 0"
46.0533 37.9721 "crf 12"
58.5997 34.6766 "crf 18"
65.2445 30.6288 "crf 23"
78.2667 25.9883 "crf 28"
118.634 21.0424 "crf 35"
EOD
$p_ultrafast << EOD
950.28 41.7574 "crf 0"
800.444 37.6694 "crf 12"
1125.4 33.8285 "crf 18"
1080.76 29.9727 "crf 23"
1110.15 25.9842 "crf 28"
1232.64 21.3444 "crf 35"
EOD
$p_veryfast << EOD
329.293 41.7574 "crf 0"
268.964 36.8899 "crf 12"
289.855 33.0563 "crf 18"
308.257 29.2822 "crf 23"
334.647 25.4941 "crf 28"
430.741 21.0533 "crf 35"
EOD
$front << EOD
950.28 41.7574
1125.4 33.8285
1232.64 21.3444
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
