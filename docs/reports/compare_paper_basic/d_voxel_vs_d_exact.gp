set terminal pngcairo size 900,640 font 'DejaVu Sans,10'
set output 'd_voxel_vs_d_exact.png'
set title 'd(C, M) per state: voxel pipeline against exact'
set xlabel 'd_{exact} [m]'
set ylabel 'd_{voxel} [m]'
set key outside right top box
set grid
set size square
plot 'd_voxel_vs_d_exact.dat' index 0 using 1:2 with points pt 7 lc 1 title 'center 16x12x12', '' index 1 using 1:2 with points pt 7 lc 2 title 'center 20x15x15', '' index 2 using 1:2 with points pt 7 lc 3 title 'center 24x18x18', '' index 3 using 1:2 with points pt 7 lc 4 title 'center 28x21x21', '' index 4 using 1:2 with points pt 7 lc 5 title 'center 32x24x24', '' index 5 using 1:2 with points pt 7 lc 6 title 'center 36x27x27', '' index 6 using 1:2 with points pt 6 ps 1.6 lc 1 title 'conservative 16x12x12', '' index 7 using 1:2 with points pt 6 ps 1.6 lc 2 title 'conservative 20x15x15', '' index 8 using 1:2 with points pt 6 ps 1.6 lc 3 title 'conservative 24x18x18', '' index 9 using 1:2 with points pt 6 ps 1.6 lc 4 title 'conservative 28x21x21', '' index 10 using 1:2 with points pt 6 ps 1.6 lc 5 title 'conservative 32x24x24', '' index 11 using 1:2 with points pt 6 ps 1.6 lc 6 title 'conservative 36x27x27', x with lines lc rgb 'gray40' dashtype 2 title 'd_{voxel} = d_{exact}'

unset output
