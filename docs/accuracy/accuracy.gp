# hail-bench accuracy: work-precision plots, one per case.
set terminal svg size 760,480 dynamic font 'sans,11'
set logscale xy
set grid
set key outside right
set xlabel 'wall time of the run (ms, stepping only)'
set ylabel 'relative error (below 1e-9 drawn at 1e-9)'
do for [c=1:words(CASES)] {
  name = word(CASES, c)
  set output 'accuracy_'.name.'.svg'
  set title name.' ('.MACHINE.')'
  plot for [v=1:words(VARIANTS)] 'accuracy_'.name.'.dat' index (v - 1) using 1:2 with linespoints title word(VARIANTS, v)
}
