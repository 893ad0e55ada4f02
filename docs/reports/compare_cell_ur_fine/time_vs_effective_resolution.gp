set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'time_vs_effective_resolution.png'
set title 'Time per evaluation against the effective resolution'
set xlabel 'finest cells along x (n_x 2^L)'
set ylabel 'ms per evaluation (log scale)'
set key top left box opaque
set grid
set logscale xy
plot 'time_vs_effective_resolution.dat' index 0 using 1:3 with linespoints title 'conservative', '' index 1 using 1:3 with points pt 7 title 'conservative, refined'

unset output
