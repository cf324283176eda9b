#!/usr/bin/env bash
# docs/figures/sections.sh VARSYM: draws docs/figures/sections.png: Hénon–Heiles surfaces of
# section x = 0 (p_x > 0) at E = 1/12 and E = 1/8, 24 orbits each started on the section at
# p_y = 0 across its width, 400 crossings each (Simpson, h = 0.05; `varsym section`).
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM}")
out=$(cd "$(dirname "$0")" && pwd)/sections.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
for e in 12 8; do
  "$varsym" section --model henon-heiles --set energy="$(echo "1/$e" | bc -l)" \
    --grid q0_2=-0.40:0.62:24 --plane q1=0 --direction + --crossings 400 \
    --time 20000 --steps 400000 -o e$e.csv --plot e$e.png
done
gnuplot <<'GP'
set terminal pngcairo size 1300,640 font ",12"
set output "sections.png"
set datafile separator ","
set multiplot layout 1,2 title "Hénon–Heiles, section x = 0 (p_x > 0): varsym section, Simpson h = 0.05"
unset key
set xlabel "y"
set ylabel "p_y"
set palette defined (0 '#1b9e77', 1 '#d95f02', 2 '#7570b3', 3 '#e7298a', 4 '#66a61e', 5 '#e6ab02')
unset colorbox
set title "E = 1/12"
plot "e12.points.csv" using 2:3:1 with points pt 7 ps 0.3 lc palette
set title "E = 1/8"
plot "e8.points.csv" using 2:3:1 with points pt 7 ps 0.3 lc palette
unset multiplot
GP
cp sections.png "$out"
echo "wrote $out"
