#!/usr/bin/env bash
# bench/compilers.sh [ROUNDS]: Simpson's step against Boost.Odeint's sb3a_mclachlan at equal
# steps (bench/compiler_step.cpp), built by g++ and by clang++ at a Release build's flags
# (-O3 -DNDEBUG), run interleaved ROUNDS times (default 5; each run the best of 7 blocks of 10^6
# steps). Prints each round, then per compiler the medians and the ratio Simpson/odeint, and
# Simpson's time under g++ over clang++ (the default compiler of `make`). `make bench` runs it.
set -eu
rounds=${1:-5}
here=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
compilers=()
for cxx in g++ clang++; do
  if command -v "$cxx" > /dev/null; then
    "$cxx" -std=c++20 -O3 -DNDEBUG -I "$here/include" -isystem /usr/include/eigen3 \
      "$here/bench/compiler_step.cpp" -o "$tmp/$cxx"
    compilers+=("$cxx")
  fi
done
echo "round compiler simpson_ns odeint_ns ratio"
for r in $(seq "$rounds"); do
  for cxx in "${compilers[@]}"; do
    read -r s o < <("$tmp/$cxx" 2> /dev/null)
    echo "$r $cxx $s $o $(awk -v s="$s" -v o="$o" 'BEGIN { printf "%.3f", s / o }')"
  done
done | tee "$tmp/rows"
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "compiler  median simpson_ns  median odeint_ns  median ratio (simpson/odeint)"
for cxx in "${compilers[@]}"; do
  s=$(awk -v c="$cxx" '$2 == c { print $3 }' "$tmp/rows" | median)
  o=$(awk -v c="$cxx" '$2 == c { print $4 }' "$tmp/rows" | median)
  q=$(awk -v c="$cxx" '$2 == c { print $5 }' "$tmp/rows" | median)
  printf '%-9s %19s %17s %30s\n' "$cxx" "$s" "$o" "$q"
  echo "$cxx $s" >> "$tmp/simpson"
done
if [ "${#compilers[@]}" -eq 2 ]; then
  awk 'NR == 1 { g = $2 } NR == 2 { c = $2 } END { printf "Simpson: g++ / clang++ = %.3f\n", g / c }' \
    "$tmp/simpson"
fi
