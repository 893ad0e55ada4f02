set terminal pngcairo size 700,640 font 'DejaVu Sans,10'
set output 'docs/reports/optimizer_paper_basic/voxel_err_vs_exact_err.png.part'
set title 'Err of random configurations: voxel against exact'
set xlabel 'exact Err [m^2]'
set ylabel 'voxel Err [m^2]'
set grid
set key top left box opaque
plot 'docs/reports/optimizer_paper_basic/voxel_err_vs_exact_err.dat' index 0 using 1:2 with points title 'center 16x12x12', 'docs/reports/optimizer_paper_basic/voxel_err_vs_exact_err.dat' index 1 using 1:2 with points title 'conservative 16x12x12', 'docs/reports/optimizer_paper_basic/voxel_err_vs_exact_err.dat' index 2 using 1:2 with points title 'center 24x18x18', 'docs/reports/optimizer_paper_basic/voxel_err_vs_exact_err.dat' index 3 using 1:2 with points title 'conservative 24x18x18', x with lines dashtype 2 title 'equal'

unset output
