#!/usr/bin/env gnuplot
#
# created Sun Nov 22 03:06:29 2026 (20261122_03:06)
#
set term wxt 0 persist
set xlabel 'i'
set grid
set datafile missing 'nan'
set ylabel '$E_k$'
set y2label 'w'
set y2tics
plot  "< bzcat gp.data.bz2" using 2:1 title '← $E_k$(i)' with lines, "< bzcat gp.data.bz2" using 2:10 title 'w(i) →' with lines axes x1y2
set term wxt 1 persist
set xlabel 'step'
set grid
set datafile missing 'nan'
set ylabel 'unb'
plot  "< bzcat gp.data.bz2" using 2:6 title '← unb(i)' with lines
set term wxt 2 persist
set xlabel 't'
set grid
set datafile missing 'nan'
set ylabel 'v_x,v_z'
plot  "< bzcat gp.data.bz2" using 5:7 title '← v_x(t)' with lines, "< bzcat gp.data.bz2" using 5:9 title '← v_z(t)' with lines
