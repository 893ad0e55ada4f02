set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'time_vs_cameras.png'
set title 'Time per iteration against cameras (timing: varies between runs)'
set xlabel 'cameras'
set ylabel 'ms per evaluation'
set grid
set key outside right top box
set style data histograms
set style histogram rowstacked
set style fill solid 0.7
set boxwidth 0.6
set yrange [0:*]
plot 'time_vs_cameras.dat' using 2:xtic(1) title 'intersection (labelling)', '' using 3 title 'clustering'

unset output
