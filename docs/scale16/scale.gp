# hail-bench scale: ns per sphere-step against spheres, and speed-up against threads.
set terminal svg size 900,420 dynamic font 'sans,11'
set key top left
set grid
set output 'ns_per_sphere_step.svg'
set logscale x 2
set xlabel 'spheres'
set ylabel 'ns per sphere-step (mean over timed steps)'
set title TITLE
plot for [t=1:THREADS] 'ns_per_sphere_step.dat' using 1:(column(t + 1)) with linespoints title sprintf('%d thread%s', t, t > 1 ? 's' : '')
set output 'speedup.svg'
unset logscale x
set xlabel 'threads'
set ylabel 'speed-up over 1 thread'
set xtics 1
plot for [k=1:COUNTS] 'speedup.dat' using 1:(column(k + 1)) with linespoints title columnheader(k + 1), x with lines dashtype 2 title 'ideal'
