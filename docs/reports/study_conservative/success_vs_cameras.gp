set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'success_vs_cameras.png'
set title 'Success against cameras'
set xlabel 'cameras'
set ylabel 'runs reaching the tolerance [%]'
set grid
set key outside right top box
set style fill solid 0.6
set boxwidth 0.6 relative
set yrange [0:105]
plot 'success_vs_cameras.dat' index 0 using 1:2 with boxes title 'success'

unset output
