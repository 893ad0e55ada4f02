set terminal pngcairo size 900,640 font 'DejaVu Sans,10'
set output 'voxel_err_vs_exact_err.png'
set title 'Err of random configurations: voxel against exact'
set xlabel 'exact Err [m²] (log scale)'
set ylabel 'voxel Err [m²] (log scale)'
set logscale xy
set grid
set size ratio -1
set key outside right top box
plot 'voxel_err_vs_exact_err.dat' index 0 using 1:2 with points pt 7 lc 1 title 'center 16x12x12', 'voxel_err_vs_exact_err.dat' index 1 using 1:2 with points pt 6 ps 1.6 lc 1 title 'conservative 16x12x12', 'voxel_err_vs_exact_err.dat' index 2 using 1:2 with points pt 7 lc 2 title 'center 24x18x18', 'voxel_err_vs_exact_err.dat' index 3 using 1:2 with points pt 6 ps 1.6 lc 2 title 'conservative 24x18x18', x with lines lc rgb 'gray40' dashtype 2 title 'voxel = exact'

unset output
