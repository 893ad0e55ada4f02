set terminal pngcairo size 640,640 font 'DejaVu Sans,10'
set output 'docs/reports/compare_paper_basic/d_voxel_vs_d_exact.png.part'
set title 'd(C, M) per state: voxel pipeline against exact'
set xlabel 'd_{exact} [m]'
set ylabel 'd_{voxel} [m]'
set key bottom right box opaque
set grid
set size square
plot 'docs/reports/compare_paper_basic/d_voxel_vs_d_exact.dat' index 0 using 1:2 with points pt 7 title 'center', '' index 1 using 1:2 with points pt 6 ps 1.5 title 'conservative', x with lines dashtype 2 title 'd_{voxel} = d_{exact}'

unset output
