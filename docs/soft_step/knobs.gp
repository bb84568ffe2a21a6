# Work-precision plot of the soft step's knobs against the passes (knobs.dat): gnuplot knobs.gp
set terminal svg size 760,480 font "sans,12"
set output "knobs.svg"
set title "terrain-rain 4k, 1 thread: solve time against error (soft step: S substeps, C cycles, R relax)"
set xlabel "solve, ms/step"
set ylabel "mean of each step's deepest sphere overlap, mm"
set key top right
set grid
plot "< grep '^soft' knobs.dat | awk '$3==0.25 && $4==1'" using 8:5:(sprintf('S %d', $2)) with labels offset 1.5,0.6 notitle, \
     "< grep '^soft' knobs.dat | awk '$3==0.25 && $4==1'" using 8:5 with linespoints pt 7 title "soft, C 0.25, R 1", \
     "< grep '^soft' knobs.dat | awk '$3==0.125 && $4==1'" using 8:5 with linespoints pt 5 title "soft, C 0.125, R 1", \
     "< grep '^soft' knobs.dat | awk '$4==0'" using 8:5 with linespoints pt 9 title "soft, C 0.25, R 0", \
     "< grep '^passes' knobs.dat" using 8:5 with points pt 13 ps 2 title "passes (16 + 8)"
