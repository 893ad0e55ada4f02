set terminal pngcairo size 900,640 font 'DejaVu Sans,10'
set output 'd_voxel_vs_d_exact.png'
set title 'd(C, M) per state: voxel pipeline against exact'
set xlabel 'd_{exact} [m]'
set ylabel 'd_{voxel} [m]'
set key outside right top box
set grid
set size square
plot 'd_voxel_vs_d_exact.dat' index 0 using 1:2 with points pt 7 lc 1 title 'center 24x20x12', '' index 1 using 1:2 with points pt 7 lc 2 title 'center 48x40x24', '' index 2 using 1:2 with points pt 6 ps 1.6 lc 1 title 'conservative 24x20x12', '' index 3 using 1:2 with points pt 6 ps 1.6 lc 2 title 'conservative 48x40x24', '' index 4 using 1:2 with points pt 2 ps 1.3 lc 1 title 'conservative, refined 24x20x12', '' index 5 using 1:2 with points pt 2 ps 1.3 lc 2 title 'conservative, refined 48x40x24', x with lines lc rgb 'gray40' dashtype 2 title 'd_{voxel} = d_{exact}'

unset output
