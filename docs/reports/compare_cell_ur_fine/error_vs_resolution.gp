set terminal pngcairo size 1100,560 font 'DejaVu Sans,10'
set output 'error_vs_resolution.png'
set title 'Voxelisation error of d(C, M) against the exact pipeline'
set xlabel 'voxel diagonal, refined: finest cell diagonal [m]'
set ylabel '|d_{voxel} - d_{exact}| [m] (log scale; 0 not shown)'
set key outside right top box
set grid
set logscale y
plot 'error_vs_resolution.dat' index 0 using 1:2 with linespoints lc 1 pt 7 title 'center: mean', '' index 0 using 1:3 with linespoints lc 1 pt 5 dt 3 title 'center: max', '' index 1 using 1:2 with linespoints lc 2 pt 7 title 'conservative: mean', '' index 1 using 1:3 with linespoints lc 2 pt 5 dt 3 title 'conservative: max', '' index 2 using 1:2 with linespoints lc 4 pt 7 title 'conservative, refined: mean', '' index 2 using 1:3 with linespoints lc 4 pt 5 dt 3 title 'conservative, refined: max', '' index 3 using 1:2 with points pt 2 ps 1.5 lc rgb '#d62728' title 'filter lost the person (not voxelisation error)', x with lines lc rgb 'gray40' dashtype 2 title 'one voxel diagonal'

unset output
