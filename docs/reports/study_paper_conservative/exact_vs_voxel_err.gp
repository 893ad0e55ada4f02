set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'exact_vs_voxel_err.png'
set title 'Exact against voxel Err of every run'
set xlabel 'voxel Err [m²] (as the optimizer saw it)'
set ylabel 'exact Err [m²]'
set logscale xy
set grid
set key outside right top box
set xrange [0.000000500:2.249863039]
set yrange [0.000000500:2.249863039]
set arrow 1 from 0.009259259, graph 0 to 0.009259259, graph 1 nohead dt 2 lc rgb 'gray40'
set arrow 2 from graph 0, first 0.009259259 to graph 1, first 0.009259259 nohead dt 2 lc rgb 'gray40'
set arrow 3 from 0.046875000, graph 0 to 0.046875000, graph 1 nohead dt 2 lc rgb 'gray40'
set arrow 4 from graph 0, first 0.046875000 to graph 1, first 0.046875000 nohead dt 2 lc rgb 'gray40'
plot 'exact_vs_voxel_err.dat' using 1:2 with points pt 7 ps 0.6 title 'runs', x with lines lc rgb 'black' title 'exact = voxel', 1/0 with lines dt 2 lc rgb 'gray40' title 'target 0.0093 … 0.0469 m²'

unset output
