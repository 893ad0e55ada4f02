set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'iterations_vs_resolution.png'
set title 'Iterations against voxel resolution'
set xlabel 'voxels (nx·ny·nz)'
set ylabel 'evaluations per run'
set grid
set key outside right top box
set yrange [0:*]
set offsets graph 0.04, graph 0.04, graph 0.06, 0
plot 'iterations_vs_resolution.dat' index 0 using 1:2:3:4 with yerrorlines title 'median, quartiles'

unset output
