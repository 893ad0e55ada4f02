set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'docs/reports/study_paper/iterations_vs_objects.png.part'
set title 'Iterations against static and dynamic objects'
set xlabel 'objects'
set ylabel 'median evaluations'
set grid
set key outside right top box
plot 'docs/reports/study_paper/iterations_vs_objects.dat' index 0 using 1:2 with linespoints title 'static objects', 'docs/reports/study_paper/iterations_vs_objects.dat' index 1 using 1:2 with linespoints title 'dynamic objects'

unset output
