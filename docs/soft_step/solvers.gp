# The two solvers on terrain-rain from 4k to 1M spheres (solvers.dat, written by
# scripts/solver_sitting.sh; blocks: passes 1 thread, passes 2 threads, soft 1, soft 2):
# gnuplot solvers.gp
set terminal svg size 1000,420 font "sans,12"
set output "solvers.svg"
set multiplot layout 1,2 title "terrain-rain: Solver::Passes against Solver::SoftStep"
set logscale x 2
set xlabel "spheres"
set format x "%.0s%c"
set grid
set key top left
set ylabel "ns per sphere-step (median run)"
plot "solvers.dat" index 0 using 1:2 with linespoints pt 7 lc 1 title "passes, 1 thread", \
     "" index 1 using 1:2 with linespoints pt 7 lc 1 dt 2 title "passes, 2 threads", \
     "" index 2 using 1:2 with linespoints pt 5 lc 2 title "soft, 1 thread", \
     "" index 3 using 1:2 with linespoints pt 5 lc 2 dt 2 title "soft, 2 threads"
set ylabel "mean of each step's deepest overlap, mm"
plot "solvers.dat" index 0 using 1:3 with linespoints pt 7 lc 1 title "passes, spheres", \
     "" index 0 using 1:4 with linespoints pt 6 lc 1 dt 2 title "passes, ground", \
     "" index 2 using 1:3 with linespoints pt 5 lc 2 title "soft, spheres", \
     "" index 2 using 1:4 with linespoints pt 4 lc 2 dt 2 title "soft, ground"
unset multiplot
