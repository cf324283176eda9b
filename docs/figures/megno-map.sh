#!/usr/bin/env bash
# docs/figures/megno-map.sh VARSYM: draws docs/figures/megno-map.png: the mean MEGNO <Y> over the
# Hénon–Heiles surface of section x = 0 (p_x > 0) at E = 1/8, a 300 × 300 grid of (y, p_y), each
# member 1000 time units of Simpson (h = 0.05) with its tangent map. Regular orbits: <Y> ≈ 2
# (dark), chaotic: large (light, clipped at 8); outside the energy surface: blank (invalid).
# About 2 minutes on 2 cores.
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM}")
out=$(cd "$(dirname "$0")" && pwd)/megno-map.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
"$varsym" ensemble --model henon-heiles --set energy=0.125 \
  --grid p0_2=-0.5:0.5:300 --grid q0_2=-0.45:0.65:300 --time 1000 --steps 20000 \
  --output hh.csv --plot megno-map.png
cp megno-map.png "$out"
echo "wrote $out"
