#!/usr/bin/env gnuplot
#
# created Sun Nov 22 03:06:29 2026 (20261122_03:06)
#
# two
# lines#
set term png; set output 'gp-png.0.png'
set xlabel 'i'
set grid
set datafile missing 'nan'
set title 'T'
set ylabel '$E_k$'
set y2label 'w'
set y2tics
plot  "< bzcat gp-png.data.bz2" using 2:1 title '← $E_k$(i)' with lines, "< bzcat gp-png.data.bz2" using 2:10 title 'w(i) →' with lines axes x1y2
set term png; set output 'gp-png.1.png'
set xlabel 'step'
set grid
set datafile missing 'nan'
set title 'T'
set ylabel 'unb'
plot  "< bzcat gp-png.data.bz2" using 2:6 title '← unb(i)' with lines
set term png; set output 'gp-png.2.png'
set xlabel 't'
set grid
set datafile missing 'nan'
set title 'T'
set ylabel 'v_x,v_z'
plot  "< bzcat gp-png.data.bz2" using 5:7 title '← v_x(t)' with lines, "< bzcat gp-png.data.bz2" using 5:9 title '← v_z(t)' with lines
