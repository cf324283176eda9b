#!/usr/bin/env bash
# docs/figures/top-vertical.sh VARSYM: draws docs/figures/top-vertical.png, the path of the heavy
# top's axis seen from above as it passes through the vertical again and again (`--model top`,
# started upright with a sideways push), with the Euler-angle model's refusal of the same start.
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM}")
out=$(cd "$(dirname "$0")" && pwd)/top-vertical.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
"$varsym" run --model top --q0 0,0,0 --v0 0.6,0,5 --time 12 --steps 12000 --every 5 -o top.csv
# The axis R e3 from the quaternion (columns 3-6: w, x, y, z).
gnuplot <<'GP'
set terminal pngcairo size 720,640 font ",11"
set output "top-vertical.png"
set datafile separator ","
set size ratio -1
set title "Heavy top through the vertical: the tip of its axis seen from above\n(varsym run --model top --q0 0,0,0 --v0 0.6,0,5; heavy-top refuses this start)"
set xlabel "x of the axis (R e_3)"
set ylabel "y of the axis"
set grid
plot "top.csv" every ::1 using (2*($4*$6+$3*$5)):(2*($5*$6-$3*$4)) with lines lw 1.5 lc rgb "#1f77b4" title "axis tip, 12 s", \
     "< echo 0,0" using 1:2 with points pt 7 ps 1.5 lc rgb "#d62728" title "the vertical"
GP
cp top-vertical.png "$out"
echo "wrote $out"
