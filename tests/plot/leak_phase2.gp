# Written by `strata plot`; run it again with `gnuplot plot.gp`.
set encoding utf8
set terminal svg size 1100,600 noenhanced font 'sans,11' background rgb 'white'
set output '/d/plot.svg'
set multiplot title 'missions/tank/tank.coral, scenario leak_phase2: aborted (exit closed_after_abort)'
set lmargin at screen 0.08
set rmargin at screen 0.80
set key outside right top
set grid back lc rgb '#dddddd'
set xrange [0:8.058]

# Depth, positive down.
set origin 0,0
set size 1,0.94
set yrange [0.65:-0.0855]
set tmargin 3.5
set ylabel 'depth (m)'
set xlabel 'simulated time (s)'
set object rect from first 0, graph 0 to first 0.2, graph 1 fc rgb '#4477aa' fs solid 0.15 noborder behind
set object rect from first 0.2, graph 0 to first 7.8, graph 1 fc rgb '#ee6677' fs solid 0.15 noborder behind
set label 'initialize' at first 0, graph 1 left offset 0.4,0.6 front
set label 'dive_from_surface' at first 0.2, graph 1 left offset 0.4,1.7 front
set arrow from first 7.8, graph 0 to first 7.8, graph 1 nohead lc rgb '#cc0000' dt 2 lw 1.5 front
set label 'dive_from_surface aborted (exit abort)' at first 7.8, graph 0.04 right offset -0.6,0 tc rgb '#cc0000' front
set arrow from first 7.9, graph 0 to first 7.9, graph 1 nohead lc rgb '#cc0000' dt 1 lw 2.5 front
set label 'mission aborted (exit closed_after_abort)' at first 7.9, graph 0.1 right offset -0.6,0 tc rgb '#cc0000' front
plot '/d/depth.dat' using 1:2 with lines lw 2 lc rgb '#0044aa' title 'depth', \
     '/d/filtered_depth.dat' using 1:2 with lines lw 1 lc rgb '#33bbee' title 'filtered depth', \
     '/d/setpoint.dat' using 1:2 with steps lw 1.5 dt 2 lc rgb '#ee7733' title 'setpoint'
unset multiplot
