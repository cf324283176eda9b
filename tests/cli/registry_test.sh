#!/usr/bin/env bash
# tests/cli/registry_test.sh VARSYM: every model of the registry (the rows of `varsym models
# --format csv` but `lagrangian` and `urdf`, which are made from their options and tested in
# expression_test.sh and urdf_test.sh) through every command that runs it: `run`,
# `ensemble` (a grid over its first parameter, or over q0_1), `converge` (Simpson's order 4; the
# rigid bodies' lgvi-4, also 4) and `section` where the model has dense output. References: the
# ensemble member's final state equals `varsym run`'s last row from the same parameters and state
# (two drivers of one stepper: the same digits), and the run's energy column stays within the
# energy watch's bound. A model added to the registry is covered without a line more here.
source "$(dirname "$0")/lib.sh" "$@"

# q_1 LINE FILE: q_1 in line LINE of a run's CSV, the third column; a rigid body's run shows its
# attitude quaternion where its ensemble shows the Euler angles: then the tilt
# theta = acos(R_33) = acos(1 - 2 (q_x^2 + q_y^2)).
q_1() {
  if head -1 "$2" | grep -q ',q_w,'; then
    awk -F, -v n="$1" 'NR == n { c = 1 - 2 * ($4 * $4 + $5 * $5);
      printf "%.17g", atan2(sqrt(1 - c * c), c) }' "$2"
  else
    awk -F, -v n="$1" 'NR == n { print $3 }' "$2"
  fi
}

"$VARSYM" models --format csv > models.csv || bad "varsym models --format csv failed"
mapfile -t names < <(awk -F, 'NR > 1 && $2 ~ /converge/ && $1 != "lagrangian" && $1 != "urdf" {
  print $1 }' models.csv | uniq)
[ "${#names[@]}" -ge 16 ] && ok || bad "only ${#names[@]} models in the registry: ${names[*]}"
for m in pendulum kepler henon-heiles double-pendulum heavy-top cart-pole acrobot chain four-bar \
  slider-crank spherical-pendulum rigid-body top pendulum-3d; do
  printf '%s\n' "${names[@]}" | grep -qx "$m" && ok || bad "$m is not in the registry's list"
done

for m in "${names[@]}"; do
  # run: 40 steps of 0.01; a header of step,t, q, p, then the model's columns, 41 rows.
  if "$VARSYM" run --model "$m" --time 0.4 --steps 40 -o "run-$m.csv" 2> err.txt; then
    [ "$(wc -l < "run-$m.csv")" -eq 42 ] && head -1 "run-$m.csv" | grep -q '^step,t,' && ok ||
      bad "$m: run wrote $(wc -l < "run-$m.csv") lines"
  else
    bad "$m: run failed: $(cat err.txt)"
  fi
  # ensemble: two members at the first scalar parameter's default (not a count that sets d, a
  # switch or a list), else at q0_1 = the run's first value; 40 steps.
  key=$(awk -F, -v m="$m" '$1 == m && $3 != "" && $7 !~ /^"?(a whole number|each|0 or 1)/ {
    print $3 "=" $5 ":" $5 ":2"; exit }' models.csv)
  [ -n "$key" ] || key="q0_1=$(q_1 2 "run-$m.csv"):$(q_1 2 "run-$m.csv"):2"
  if "$VARSYM" ensemble --model "$m" --grid "$key" --time 0.4 --steps 40 -o "ens-$m.csv" \
    2> err.txt; then
    [ "$(awk -F, 'NR > 1 && $3 == "completed"' "ens-$m.csv" | wc -l)" -eq 2 ] && ok ||
      bad "$m: ensemble members did not complete: $(cat "ens-$m.csv")"
    # The member's last q_1 is the run's (same stepper, same start): compare 12 digits.
    d=$(head -1 "run-$m.csv" | tr ',' '\n' | grep -c '^q')
    col_ens=$(head -1 "ens-$m.csv" | tr ',' '\n' | grep -nx 'q_1\|q' | cut -d: -f1)
    a=$(q_1 "$(wc -l < "run-$m.csv")" "run-$m.csv")
    b=$(awk -F, 'NR == 2' "ens-$m.csv" | cut -d, -f"$col_ens")
    numbers "$m: ensemble q_1" "$a" "$b" && awk -v a="$a" -v b="$b" 'BEGIN { e = a - b; if (e < 0) e = -e; exit !(e <= 1e-12 * (1 + (a < 0 ? -a : a))) }' &&
      ok || bad "$m: ensemble q_1 $b differs from run's $a (d = $d)"
  else
    bad "$m: ensemble failed: $(cat err.txt)"
  fi
  # converge: Simpson's observed order is 4 on every model (against the exact solution, or gauss-8
  # at twice the finest step count); over 1 s for the models without a period. The chain's
  # default (64 masses in their lowest mode, period 130 s) moves too slowly for 1 s to leave more
  # than round-off: 4 masses over 20 s instead. Its sections need the same.
  # The rigid bodies run their own integrator (lgvi-4, also of order 4): no --scheme.
  conv=(--time 1 --steps 100,200,400,800)
  head -1 "run-$m.csv" | grep -q ',q_w,' || conv+=(--scheme simpson)
  # Sections cross q1 = its value in the run at t = 0.2 (a plane the orbit meets: some models'
  # q1 never returns to 0, the heavy top's precession angle), the chain's q1 = 0.
  sec=(--plane "q1=$(awk -F, 'NR == 22 { print $3 }' "run-$m.csv")")
  if [ "$m" = chain ]; then
    conv=(--set n=4 --set amplitude=1.5 --time 20 --steps 50,100,200,400 --scheme simpson)
    sec=(--set n=4 --plane q1=0)
  fi
  if "$VARSYM" converge --model "$m" "${conv[@]}" > conv.txt 2> err.txt; then
    awk '$1 == "fitted" { exit !($3 > 3.7 && $3 < 4.3) }' conv.txt && ok ||
      bad "$m: Simpson's fitted order is not 4: $(grep fitted conv.txt)"
  else
    bad "$m: converge failed: $(cat err.txt)"
  fi
  # section, where the model has dense output: crossings of the plane above, both directions.
  if awk -F, -v m="$m" '$1 == m && $2 ~ /section/ { found = 1 } END { exit !found }' models.csv; then
    "$VARSYM" section --model "$m" --grid "$key" "${sec[@]}" --time 20 --steps 2000 --direction both \
      --crossings 3 -o "sec-$m.csv" \
      2> err.txt && [ "$(wc -l < "sec-$m.csv")" -ge 3 ] && ok ||
      bad "$m: section: $(cat err.txt) $(head -3 "sec-$m.csv" 2> /dev/null)"
  fi
done

# A member's start is the model's default at the member's parameters where --q0/--p0 do not give
# it: the spherical pendulum's default rate sqrt(g/l) follows each member's g. Member 0 (g = 1)
# ends where `varsym run --gravity 1` does; member 1 (g = 9) elsewhere (the negative control).
"$VARSYM" ensemble --model spherical-pendulum --grid gravity=1:9:2 --time 0.4 --steps 40 \
  -o ens-g.csv 2> err.txt &&
  "$VARSYM" run --model spherical-pendulum --gravity 1 --time 0.4 --steps 40 -o run-g.csv &&
  a=$(tail -1 run-g.csv | cut -d, -f3) && b=$(awk -F, 'NR == 2 { print $6 }' ens-g.csv) &&
  c=$(awk -F, 'NR == 3 { print $6 }' ens-g.csv) && numbers "ensemble start" "$a" "$b" "$c" &&
  awk -v a="$a" -v b="$b" -v c="$c" 'BEGIN { e = a - b; f = a - c; if (e < 0) e = -e;
    if (f < 0) f = -f; exit !(e <= 1e-12 && f > 1e-3) }' && ok ||
  bad "ensemble start at the member's parameters: run $a, members $b $c $(cat err.txt)"
expect_error 2 "a dimension as a member's key" "n sets the number of coordinates, which the members share" ensemble --model chain --grid n=2:4:3 -o out.csv

# The progress line: on a terminal (a pseudo-terminal from script(1)) stderr shows it, stdout
# stays the CSV alone; --quiet, or stderr not a terminal, shows none.
if command -v script > /dev/null; then
  script -qec "'$VARSYM' run --model henon-heiles --time 2000 --steps 1000000 --every 0 -o p.csv" \
    /dev/null > tty.txt 2>&1
  grep -q 'varsym run: 1000000/1000000 steps (100.0 %)' tty.txt && ok ||
    bad "no progress line on a terminal: $(tr '\r' '\n' < tty.txt | tail -2)"
  script -qec "'$VARSYM' run --model henon-heiles --time 2000 --steps 1000000 --every 0 -q -o p.csv" \
    /dev/null > tty.txt 2>&1
  [ ! -s tty.txt ] && ok || bad "--quiet still printed: $(cat tty.txt)"
  "$VARSYM" run --model henon-heiles --time 2000 --steps 1000000 --every 0 > out.txt 2> err.txt
  [ ! -s err.txt ] && [ "$(wc -l < out.txt)" -eq 2 ] && ok || bad "progress off a terminal: $(cat err.txt)"
  rm -f out.txt
else
  skip "the progress line on a terminal: script(1) is missing (util-linux)"
fi

# Negative control for the orders: Newmark's is 2 (on the acrobot, against gauss-8).
"$VARSYM" converge --model acrobot --scheme newmark --time 1 --steps 100,200,400,800 > conv.txt &&
  awk '$1 == "fitted" { exit !($3 > 1.8 && $3 < 2.2) }' conv.txt && ok ||
  bad "Newmark's fitted order on the acrobot is not 2: $(grep fitted conv.txt)"
expect_error 2 "converge --set on the pendulum" "--set is for the other models; the pendulum's parameters" converge --set mass=2 -o out.csv
expect_error 2 "converge --mass on kepler" "--mass is the pendulum's; give kepler's parameters and" converge --model kepler --mass 2 -o out.csv

# A model's parameter on another model is refused; a typo in a model's name names the model.
expect_error 2 "another model's parameter" "--push is a parameter of --model cart-pole, not of --model acrobot" run --model acrobot --push 1 -o out.csv
expect_error 2 "unknown model" "--model: acrobat not in" run --model acrobat -o out.csv
expect_error 2 "parameter out of range" "--pole-mass: pole_mass must be positive, got 0" run --model cart-pole --pole-mass 0 -o out.csv
finish
