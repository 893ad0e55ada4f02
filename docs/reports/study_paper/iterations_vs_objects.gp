set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'iterations_vs_objects.png'
set title 'Iterations against static and dynamic objects'
set xlabel 'objects'
set ylabel 'median evaluations'
set grid
set key outside right top box
plot 'iterations_vs_objects.dat' index 0 using 1:2 with linespoints title 'static objects', 'iterations_vs_objects.dat' index 1 using 1:2 with linespoints title 'dynamic objects'

unset output
