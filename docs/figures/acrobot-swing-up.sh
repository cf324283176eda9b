#!/usr/bin/env bash
# docs/figures/acrobot-swing-up.sh VARSYM: draws docs/figures/acrobot-swing-up.png: the acrobot
# (two uniform links of 1 kg and 1 m, torque at the elbow only) swung from hanging at rest to
# upright at rest in 4 s at least effort (varsym optimize, Simpson, 80 steps): the joint angles,
# the elbow torque at the quadrature points, and a strip of poses every 0.5 s (80 steps refined
# from 40: --refine 1).
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM}")
out=$(cd "$(dirname "$0")" && pwd)/acrobot-swing-up.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
"$varsym" optimize --model acrobot --time 4 --steps 80 --from 0,0 --to 3.141592653589793,0 \
  --refine 1 --quiet --output nodes.csv --controls controls.csv
# Poses at every 10th node (0.5 s), shifted right by 2.6 m each: pivot, elbow, tip.
awk -F, 'NR > 1 && (NR - 2) % 10 == 0 { x0 = 2.6 * k++; e1 = x0 + sin($2); e2 = -cos($2);
  printf "%g 0\n%g %g\n%g %g\n\n", x0, e1, e2, e1 + sin($2 + $3), e2 - cos($2 + $3) }' \
  nodes.csv > poses.dat
gnuplot <<'GP'
set terminal pngcairo size 1100,900 font ",11"
set output "acrobot-swing-up.png"
set datafile separator ","
set multiplot layout 3,1 title "Acrobot swing-up at least effort: varsym optimize (Simpson, N = 80, IPOPT)"
set xlabel "t [s]"; set ylabel "angle [rad]"; set key top left; set grid
plot "nodes.csv" using 1:2 skip 1 with lines lw 2 title "q1 (shoulder, from hanging)", \
     "" using 1:3 skip 1 with lines lw 2 title "q2 (elbow, relative)"
set ylabel "u [N m]"
plot "controls.csv" using 1:2 skip 1 with linespoints pt 7 ps 0.4 lw 1.5 title "elbow torque u"
set datafile separator whitespace
unset xlabel; set ylabel "poses every 0.5 s"; unset key; unset grid; set xrange [-1.3:22.1]; set yrange [-2.2:2.2]
set size ratio -1; unset xtics; set ytics -2,1,2
plot "poses.dat" using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb "#1f5fa8"
unset multiplot
GP
cp acrobot-swing-up.png "$out"
echo "wrote $out"
