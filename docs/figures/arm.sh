#!/usr/bin/env bash
# docs/figures/arm.sh VARSYM: draws docs/figures/arm.png: a three-link arm (`--model arm`)
# lifted from hanging to the joint angles (0.8, 0.5, 0.3) by its PD controller along a
# minimum-jerk move of 2 s; its joint angles, the tracking error, and the energy balance
# E − E0 − W (the scheme's error: the forces' work W is accounted for to ~1e-12 J).
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM}")
out=$(cd "$(dirname "$0")" && pwd)/arm.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
"$varsym" run --model arm --time 6 --steps 6000 --every 10 -o arm.csv
# Columns: 2 t, 3-5 link angles, 9 energy, 10 work, 11 energy_balance, 12 tracking_error.
gnuplot <<'GP'
set terminal pngcairo size 760,640 font ",11"
set output "arm.png"
set datafile separator ","
set multiplot layout 2,1 title "Three-link arm under joint PD control (varsym run --model arm, Simpson, h = 1 ms)"
set grid
set key right bottom
set ylabel "joint angle [rad]"
set xlabel "t [s]"
plot "arm.csv" every ::1 using 2:3 with lines lw 2 title "φ_1 = θ_1", \
     "" every ::1 using 2:($4-$3) with lines lw 2 title "φ_2 = θ_2 − θ_1", \
     "" every ::1 using 2:($5-$4) with lines lw 2 title "φ_3 = θ_3 − θ_2", \
     0.8 with lines dt 2 lc rgb "gray" notitle, 0.5 with lines dt 2 lc rgb "gray" notitle, \
     0.3 with lines dt 2 lc rgb "gray" title "targets"
set logscale y
set format y "10^{%L}"
set ylabel "error"
set key right top
plot "arm.csv" every ::2 using 2:(abs($12) > 0 ? abs($12) : 1/0) with lines lw 2 title "tracking error max|φ − r(t)| [rad]", \
     "" every ::2 using 2:(abs($11) > 0 ? abs($11) : 1/0) with lines lw 2 title "energy balance |E − E_0 − W| [J]"
unset multiplot
GP
cp arm.png "$out"
echo "wrote $out"
