set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'memory_vs_resolution.png'
set title 'Peak memory against resolution (varies between runs)'
set xlabel 'voxels (nx·ny·nz)'
set ylabel 'peak memory of a run [MiB]'
set grid
set key outside right top box
set yrange [0:*]
set offsets graph 0.04, graph 0.04, graph 0.06, 0
plot 'memory_vs_resolution.dat' index 0 using 1:2 with linespoints title 'virtual (VmPeak)', 'memory_vs_resolution.dat' index 1 using 1:2 with linespoints title 'resident (VmHWM)'

unset output
