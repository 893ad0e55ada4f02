set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'docs/reports/study_conservative/iterations_vs_resolution.png.part'
set title 'Iterations against voxel resolution'
set xlabel 'voxels (nx·ny·nz)'
set ylabel 'median evaluations'
set grid
set key outside right top box
plot 'docs/reports/study_conservative/iterations_vs_resolution.dat' index 0 using 1:2 with linespoints title 'median evaluations'

unset output
