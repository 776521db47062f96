# Written by `strata plot`; run it again with `gnuplot plot.gp`.
set encoding utf8
set terminal svg size 1100,800 noenhanced font 'sans,11' background rgb 'white'
set output '/d/plot.svg'
set multiplot title 'missions/survey/box.coral, scenario compass_drift: aborted (exit closed_after_abort)'
set lmargin at screen 0.08
set rmargin at screen 0.80
set key outside right top
set grid back lc rgb '#dddddd'
set xrange [0:6.12]

# Depth, positive down.
set origin 0,0.36
set size 1,0.60
set yrange [1.575:-0.075]
set tmargin 3.5
set ylabel 'depth (m)'
set xlabel
set format x ''
set object rect from first 0, graph 0 to first 2.5, graph 1 fc rgb '#4477aa' fs solid 0.15 noborder behind
set object rect from first 2.5, graph 0 to first 5.5, graph 1 fc rgb '#ee6677' fs solid 0.15 noborder behind
set object rect from first 3, graph 0.976 to first 4.5, graph 1 fc rgb '#555555' fs solid 0.45 noborder behind
set label 'descend' at first 0, graph 1 left offset 0.4,0.6 front
set label 'turn_leg' at first 2.5, graph 1 left offset 0.4,1.7 front
set arrow from first 4.5, graph 0 to first 4.5, graph 1 nohead lc rgb '#cc0000' dt 2 lw 1.5 front
set label 'hold_heading aborted (exit drifted)' at first 4.5, graph 0.04 right offset -0.6,0 tc rgb '#cc0000' front
set arrow from first 5.5, graph 0 to first 5.5, graph 1 nohead lc rgb '#cc0000' dt 2 lw 1.5 front
set label 'turn_leg aborted (exit abort)' at first 5.5, graph 0.1 right offset -0.6,0 tc rgb '#cc0000' front
set arrow from first 6, graph 0 to first 6, graph 1 nohead lc rgb '#cc0000' dt 1 lw 2.5 front
set label 'mission aborted (exit closed_after_abort): compass drift' at first 6, graph 0.16 right offset -0.6,0 tc rgb '#cc0000' front
plot '/d/depth.dat' using 1:2 with lines lw 2 lc rgb '#0044aa' title 'depth', \
     '/d/filtered_depth.dat' using 1:2 with lines lw 1 lc rgb '#33bbee' title 'filtered depth', \
     '/d/setpoint.dat' using 1:2 with steps lw 1.5 dt 2 lc rgb '#ee7733' title 'setpoint'

# Heading, on the same time axis.
unset object
unset label
unset arrow
set origin 0,0
set size 1,0.38
set tmargin 1
set yrange [0:360]
set ytics 0,90,360
set ylabel 'heading (deg)'
set xlabel 'simulated time (s)'
set format x
set object rect from first 0, graph 0 to first 2.5, graph 1 fc rgb '#4477aa' fs solid 0.15 noborder behind
set object rect from first 2.5, graph 0 to first 5.5, graph 1 fc rgb '#ee6677' fs solid 0.15 noborder behind
set arrow from first 4.5, graph 0 to first 4.5, graph 1 nohead lc rgb '#cc0000' dt 2 lw 1.5 front
set arrow from first 5.5, graph 0 to first 5.5, graph 1 nohead lc rgb '#cc0000' dt 2 lw 1.5 front
set arrow from first 6, graph 0 to first 6, graph 1 nohead lc rgb '#cc0000' dt 1 lw 2.5 front
plot '/d/heading.dat' using 1:2 with lines lw 1.5 lc rgb '#009988' title 'heading'
unset multiplot
