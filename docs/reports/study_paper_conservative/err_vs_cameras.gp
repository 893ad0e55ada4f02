set terminal pngcairo size 800,560 font 'DejaVu Sans,10'
set output 'err_vs_cameras.png'
set title 'Final Err against cameras'
set xlabel 'cameras (below: runs that reached the target / runs)' offset 0,-1
set bmargin 5
set grid ytics
set key outside right top box
set xrange [-0.6:6.6]
set ylabel 'final Err of a run [m²] (log scale)'
set logscale y
set yrange [0.007266887:0.462762210]
set boxwidth 0.5
set style fill solid 0.3 border -1
set xtics scale 0
plot 'err_vs_cameras.dat' using 1:4:3:7:6:xtic(sprintf("%s\n%d/%d", stringcolumn(2), $9, $10)) with candlesticks whiskerbars 0.5 lc rgb '#1f77b4' title 'Err: quartiles, min–max', 'err_vs_cameras.dat' using 1:5:5:5:5 with candlesticks lw 2 lc rgb 'black' title 'median', 'err_vs_cameras.dat' using 1:8 with points pt 6 ps 1.5 lc rgb '#d62728' title 'success target'

unset output
