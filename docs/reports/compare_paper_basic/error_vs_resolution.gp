set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'docs/reports/compare_paper_basic/error_vs_resolution.png.part'
set title 'Voxelisation error of d(C, M) against the exact pipeline'
set xlabel 'voxel diagonal [m]'
set ylabel '|d_{voxel} - d_{exact}| [m] (log scale; 0 not shown)'
set key top left box opaque
set grid
set logscale y
plot 'docs/reports/compare_paper_basic/error_vs_resolution.dat' index 0 using 1:2 with linespoints title 'center: mean', '' index 0 using 1:3 with linespoints title 'center: max', '' index 1 using 1:2 with linespoints title 'conservative: mean', '' index 1 using 1:3 with linespoints title 'conservative: max', x with lines dashtype 2 title 'one voxel diagonal'

unset output
