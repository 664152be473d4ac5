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
set xrange [25.8302:1003.33]
set yrange [19.04:43.7566]
$p_medium << EOD
70.9888 41.7566 "crf 0"
40.321 37.9091 "crf 12"
50.6198 34.6435 "crf 18"
57.4152 30.6322 "crf 23"
65.6776 26.0037 "crf 28"
59.6621 21.1233 "crf 35"
EOD
$p_slow << EOD
77.7426 41.7566 "crf 0"
38.7452 37.9937 "crf 12"
40.8698 34.6727 "crf 18"
40.4734 30.6636 "crf 23"
55.2836 25.9804 "crf 28"
78.7744 21.04 "crf 35"
EOD
$p_ultrafast << EOD
500.371 41.7566 "crf 0"
546.431 37.6849 "crf 12"
620.67 33.872 "crf 18"
662.923 30.0008 "crf 23"
668.889 25.9639 "crf 28"
651.224 21.4005 "crf 35"
EOD
$p_veryfast << EOD
181.539 41.7566 "crf 0"
136.953 36.9033 "crf 12"
142.242 33.0501 "crf 18"
146.73 29.2865 "crf 23"
154.549 25.5032 "crf 28"
199.202 21.0663 "crf 35"
EOD
$front << EOD
500.371 41.7566
546.431 37.6849
620.67 33.872
662.923 30.0008
668.889 25.9639
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
