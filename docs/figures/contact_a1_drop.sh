#!/usr/bin/env bash
# docs/figures/contact_a1_drop.sh VARSYM: draws docs/figures/contact_a1_drop.png: the Unitree A1
# (tests/data/urdf/a1.urdf, a free base) dropped from 0.3 m above its stance onto the ground
# under joint PD control (kp 80, kd 2, holding its crouch): the base's height, and the contact
# forces (the step's normal and friction impulses over h) with the number of feet in contact.
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM}")
urdf=$(cd "$(dirname "$0")/../../tests/data/urdf" && pwd)/a1.urdf
out=$(cd "$(dirname "$0")" && pwd)/contact_a1_drop.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
legs=0,0.8,-1.5,0,0.8,-1.5,0,0.8,-1.5,0,0.8,-1.5
"$varsym" run --urdf "$urdf" --base free --contact --q0 0,0,0.6135,1,0,0,0,$legs \
  --kp 80,80,80,80,80,80,80,80,80,80,80,80 --kd 2,2,2,2,2,2,2,2,2,2,2,2 --target $legs \
  --scheme gauss --degree 2 --time 1.5 --steps 1500 -o drop.csv
# Columns: 2 t, 5 q_base_z, 61 contacts, 62 normal_impulse, 63 friction_impulse, 64 penetration.
gnuplot <<'GP'
set terminal pngcairo size 760,640 font ",11"
set output "drop.png"
set datafile separator ","
set multiplot layout 2,1 title "Unitree A1 dropped from 0.3 m (varsym run --contact, gauss-2, h = 1 ms)"
set grid
set key right top
set ylabel "base height [m]"
plot "drop.csv" every ::1 using 2:5 with lines lw 2 title "base z (q\\_base\\_z)"
set ylabel "force [N]"
set y2label "feet in contact"
set key right center
set y2range [0:5]
set y2tics 0,1,4
set xlabel "t [s]"
plot "drop.csv" every ::1 using 2:($62/0.001) with lines lw 2 title "normal (sum over the feet)", \
     "" every ::1 using 2:($63/0.001) with lines lw 2 title "friction (sum of |b|)", \
     "" every ::1 using 2:61 axes x1y2 with steps lw 1 lc rgb "gray" title "feet in contact"
unset multiplot
GP
cp drop.png "$out"
echo "wrote $out"
