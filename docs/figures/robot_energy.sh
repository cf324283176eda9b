#!/usr/bin/env bash
# docs/figures/robot_energy.sh BUILD_DIR: draws docs/figures/robot_energy.png: the relative
# energy error of the UR5 (tests/data/urdf/ur5_robot.urdf) swinging freely from rest for 10^6
# steps of 1 ms, varsym's gauss-2 against MuJoCo's RK4 and semi-implicit Euler on the same
# file (bench/bench_robots.cpp, section energy; `make bench-robots` builds it).
set -eu
build=$(realpath "${1:?usage: $0 BUILD_DIR}")
out=$(cd "$(dirname "$0")" && pwd)/robot_energy.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/bench/varsym_bench_robots" energy "$tmp/energy.csv"
cd "$tmp"
gnuplot <<'GP'
set terminal pngcairo size 820,480 font ",11"
set output "robot_energy.png"
set datafile separator ","
set title "UR5 swinging freely, 10^6 steps of 1 ms: relative energy error |E - E_0| / E_0"
set logscale y
set format y "10^{%L}"
set yrange [1e-15:10]
set grid
set key left top
set xlabel "t [s]"
set ylabel "|E - E_0| / E_0"
plot "energy.csv" every ::1 using 2:(abs($4)) with lines lw 2 title "MuJoCo RK4 (order 4)", \
     "" every ::1 using 2:(abs($5)) with lines lw 2 title "MuJoCo semi-implicit Euler", \
     "" every ::1 using 2:(abs($3) > 1e-15 ? abs($3) : 1e-15) with lines lw 2 title "varsym gauss-2 (order 4, symplectic)"
GP
mv robot_energy.png "$out"
