#!/usr/bin/env bash
# docs/figures/cart-pole-fall.sh VARSYM: draws docs/figures/cart-pole-fall.png: how long the
# cart-pole's pole stays up (|th| < 1.57 rad) over a 121 × 121 grid of constant pushes u
# (-2..2 N) and initial tilts th0 (-0.3..0.3 rad), from rest; Simpson, h = 2 ms, 5 s. The
# longest survivals lie on the line where the push balances the tilt at the start: the cart's
# acceleration u/(M + m) equals g tan th0 (about u = 10.8 th0 with the default masses). At
# u = th0 = 0 the upright equilibrium never falls (blank: no event).
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM}")
out=$(cd "$(dirname "$0")" && pwd)/cart-pole-fall.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
"$varsym" ensemble --model cart-pole --grid push=-2:2:121 --grid q0_2=-0.3:0.3:121 \
  --event 'q2^2 - 2.4649' --no-indicators --time 5 --steps 2500 \
  --output fall.csv --plot cart-pole-fall.png --plot-value event_time
cp cart-pole-fall.png "$out"
echo "wrote $out"
