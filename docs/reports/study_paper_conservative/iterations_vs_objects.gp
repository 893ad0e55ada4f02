set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'iterations_vs_objects.png'
set title 'Iterations against static and dynamic objects'
set xlabel 'objects'
set ylabel 'evaluations per run'
set grid
set key outside right top box
set yrange [0:*]
set offsets graph 0.04, graph 0.04, graph 0.06, 0
plot 'iterations_vs_objects.dat' index 0 using 1:2:3:4 with yerrorlines title 'static objects: median, quartiles', 'iterations_vs_objects.dat' index 1 using 1:2:3:4 with yerrorlines title 'dynamic objects: median, quartiles'

unset output
