set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'iterations_vs_resolution.png'
set title 'Iterations against voxel resolution'
set xlabel 'voxels (nx·ny·nz)'
set ylabel 'median evaluations'
set grid
set key outside right top box
plot 'iterations_vs_resolution.dat' index 0 using 1:2 with linespoints title 'median evaluations'

unset output
