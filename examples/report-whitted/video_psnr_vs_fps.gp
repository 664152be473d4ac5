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
set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05
$p_medium << EOD
75.3308 41.7566 "crf 0"
54.2479 37.9091 "crf 12"
62.6119 34.6435 "crf 18"
60.634 30.6322 "crf 23"
67.3383 26.0037 "crf 28"
92.2762 21.1233 "crf 35"
EOD
$p_slow << EOD
56.5282 41.7566 "crf 0"
28.6687 37.9937 "crf 12"
26.7695 34.6727 "crf 18"
25.7176 30.6636 "crf 23"
34.1792 25.9804 "crf 28"
50.0923 21.04 "crf 35"
EOD
$p_ultrafast << EOD
471.785 41.7566 "crf 0"
424.824 37.6849 "crf 12"
478.549 33.872 "crf 18"
496.37 30.0008 "crf 23"
499.306 25.9639 "crf 28"
545.937 21.4005 "crf 35"
EOD
$p_veryfast << EOD
134.718 41.7566 "crf 0"
105.761 36.9033 "crf 12"
119.921 33.0501 "crf 18"
125.274 29.2865 "crf 23"
180.052 25.5032 "crf 28"
211.568 21.0663 "crf 35"
EOD
$front << EOD
471.785 41.7566
478.549 33.872
496.37 30.0008
499.306 25.9639
545.937 21.4005
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
