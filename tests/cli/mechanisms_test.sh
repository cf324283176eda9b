#!/usr/bin/env bash
# tests/cli/mechanisms_test.sh VARSYM: the mechanisms of `varsym run` (forces and constraints):
# arm, four-bar, slider-crank, spherical-pendulum. References: the constraints and their hidden
# (velocity) constraint, which hold to round-off; the energy balance E − E0 = W (the forces'
# work), which holds to the scheme's error; the spin of the spherical pendulum (a symmetry); the
# arm's controller, which must bring the joints to their target. Bounds are from runs measured
# on this build, with margins stated beside them.
source "$(dirname "$0")/lib.sh" "$@"

# max_abs FILE COLUMN: the largest |value| of a column over the data rows; nothing (which le
# refuses) when the file has no data row.
max_abs() { awk -F, -v c="$2" 'NR > 1 { x = $c; if (x < 0) x = -x; if (x > m) m = x }
  END { if (NR > 1) printf "%.3e", m }' "$1"; }

# --- four-bar: 10 s, Simpson, h = 1e-3; E0 = 89.1 J -------------------------------------------
# Columns: 9 energy, 10 work, 11 energy_balance, 12 constraint_residual, 13 hidden_residual,
# 14-15 lambda. Measured: balance at most 1.8e-9 (2e-11 of E0), residuals 6e-15 and 4e-15.
"$VARSYM" run --model four-bar --every 10 > fb.csv || bad "four-bar run: $(cat stderr.txt)"
le "$(max_abs fb.csv 12)" 1e-13 && le "$(max_abs fb.csv 13)" 1e-13 && ok ||
  bad "four-bar residuals $(max_abs fb.csv 12) $(max_abs fb.csv 13)"
le "$(max_abs fb.csv 11)" 1e-8 && ok || bad "four-bar energy balance $(max_abs fb.csv 11)"
# Not vacuous: the crank turned (th1 grew by more than 2 pi) and the loop carried forces.
awk -F, 'NR == 2 { a = $3 } END { exit !($3 - a > 6.3) }' fb.csv && le 1 "$(max_abs fb.csv 15)" && ok ||
  bad "four-bar did not turn: $(tail -1 fb.csv)"
# Newmark's balance is larger (order 2 against Simpson's 4; measured 3.1e-4): the column
# measures the scheme.
"$VARSYM" run --model four-bar --time 2 --steps 2000 --every 10 --scheme newmark > fbn.csv &&
  le 1e-6 "$(max_abs fbn.csv 11)" && ok || bad "four-bar newmark balance $(max_abs fbn.csv 11)"

# --- slider-crank driven by a torque: the work is not zero, the balance still holds ------------
# The torque spins the crank up (work 178 J in 5 s); the balance's error grows with the speed to
# 1.9e-6 (1.1e-8 of the work), bound 1e-7 of the work.
"$VARSYM" run --model slider-crank --torque 2 --every 10 > sc.csv || bad "slider-crank run"
le 100 "$(max_abs sc.csv 10)" && le "$(max_abs sc.csv 11)" "$(awk -v w="$(max_abs sc.csv 10)" 'BEGIN { if (w != "") print 1e-7 * w }')" && ok ||
  bad "slider-crank work $(max_abs sc.csv 10) balance $(max_abs sc.csv 11)"
le "$(max_abs sc.csv 12)" 1e-13 && le "$(max_abs sc.csv 13)" 1e-12 && ok ||
  bad "slider-crank residuals $(max_abs sc.csv 12) $(max_abs sc.csv 13)"

# --- spherical pendulum: the spin x p_y - y p_x (column 15) is the same on every row to 1e-14 ---
"$VARSYM" run --model spherical-pendulum --scheme gauss --degree 3 > sp.csv || bad "spherical run"
awk -F, 'NR == 2 { s = $15 } NR > 2 { d = $15 - s; if (d < 0) d = -d; if (d > m) m = d }
         END { exit !(m <= 1e-14 * s && NR == 2002) }' sp.csv && ok || bad "spherical spin drifts"
le "$(max_abs sp.csv 12)" 1e-14 && le "$(max_abs sp.csv 13)" 1e-13 && ok || bad "spherical residuals"

# --- arm: 3 links reach their target; gravity compensation is what makes the error vanish ------
# Columns: 3-5 th, 9 energy, 10 work, 11 energy_balance, 12 tracking_error (max |phi - r(t)|).
# Measured at t = 10: tracking 1e-7 rad; without compensation the joints sag by 0.2 rad.
"$VARSYM" run --model arm --time 10 --steps 10000 --every 100 > arm.csv || bad "arm run"
tail -1 arm.csv | awk -F, '{ exit !($12 < 1e-5) }' && ok || bad "arm missed its target: $(tail -1 arm.csv)"
le "$(max_abs arm.csv 11)" 1e-9 && le 1 "$(max_abs arm.csv 10)" && ok ||
  bad "arm energy balance $(max_abs arm.csv 11), work $(max_abs arm.csv 10)"
"$VARSYM" run --model arm --time 5 --steps 5000 --every 0 --no-gravity-compensation > sag.csv &&
  tail -1 sag.csv | awk -F, '{ exit !($12 > 1e-2) }' && ok || bad "arm without compensation: $(tail -1 sag.csv)"
# Six links, gauss-2.
"$VARSYM" run --model arm --masses 1,1,1,1,1,1 --lengths 0.5,0.5,0.5,0.5,0.5,0.5 --scheme gauss \
  --degree 2 --time 2 --steps 2000 --every 0 > arm6.csv && ok || bad "arm of six links: $(cat stderr.txt)"

# --- a forced run killed and resumed continues bit for bit (the work is in the checkpoint) -----
# 1e5 steps of the arm (about 1 s in Release), killed as soon as its first checkpoint exists.
aargs=(run --model arm --time 10 --steps 100000 --every 1000)
"$VARSYM" "${aargs[@]}" -o a_straight.csv || bad "arm straight run"
"$VARSYM" "${aargs[@]}" -o a.csv --checkpoint a.ckpt --checkpoint-every 10000 & pid=$!
for i in $(seq 1 6000); do [ -e a.ckpt ] && break; sleep 0.01; done
kill -9 $pid 2> /dev/null; { wait $pid; } 2> /dev/null
[ -e a.csv.part ] && [ ! -e a.csv ] && ok || bad "the arm run ended before it was killed"
"$VARSYM" run --resume a.ckpt 2> stderr.txt && cmp -s a.csv a_straight.csv && ok ||
  bad "arm resume: $(cat stderr.txt)"

# --- bad input: exit 2 -------------------------------------------------------------------------
expect_error 2 "four-bar off its loop" "four-bar: the initial position is off the constraints: max" run --model four-bar --q0 1,0.5,1.5 -o out.csv
grep -q -- '--project' stderr.txt && ok || bad "no --project advice: $(cat stderr.txt)"
"$VARSYM" run --model four-bar --q0 1,0.5,1.5 --project --time 0.1 --steps 100 --every 0 > fp.csv &&
  le "$(max_abs fp.csv 12)" 1e-13 && ok || bad "four-bar --project: $(tail -1 fp.csv)"
expect_error 2 "four-bar velocity off its loop" "four-bar: the initial velocity is not tangent to the" run --model four-bar --v0 1,1,1 -o out.csv
expect_error 2 "four-bar that cannot close" "four-bar: the four-bar cannot close at this crank angle" run --model four-bar --lengths 1,1,1,5 -o out.csv
expect_error 2 "four-bar wrong lengths" "four-bar: --lengths needs 4 values, got 2" run --model four-bar --lengths 1,2 -o out.csv
expect_error 2 "constrained with the simplified iteration" "slider-crank: a constrained model is solved by Newton: use" run --model slider-crank --iteration simplified -o out.csv
expect_error 2 "slider-crank rod shorter than crank" "slider-crank: the rod must be longer than the crank (l > r)" run --model slider-crank --lengths 1,0.5 -o out.csv
expect_error 2 "spherical off the sphere" "spherical-pendulum: the initial position is off the" run --model spherical-pendulum --q0 0,0,-1.1 -o out.csv
expect_error 2 "arm lengths missing" "arm: give the lengths of the 2 links" run --model arm --masses 1,1 -o out.csv
expect_error 2 "arm target count" "arm: target needs 3 values (one per link), got 1" run --model arm --target 1 -o out.csv
expect_error 2 "arm negative gain" "--kp: kp must be non-negative, got -1" run --model arm --kp -1,1,1 -o out.csv
expect_error 2 "arm option on four-bar" "--kp is a parameter of --model arm, not of --model four-bar" run --model four-bar --kp 1,1,1 -o out.csv
# A crank torque so large that h = 0.1 cannot follow: exit 3, rows kept.
expect_error 3 "four-bar diverging" "Newton's method did not converge in step 1 (t = 0 -> 0.1)" run --model four-bar --torque 1e6 --time 10 --steps 100 -o out.csv
rm -f out.csv.part
# The parallelogram four-bar reaches its change point (all links collinear, at t = 1.34 s): the
# step fails with its cause named (a nearly singular constraint Jacobian), rows kept. The default
# four-bar, a crank-rocker, turns through the same time (the first check above).
expect_error 3 "four-bar change point" "the constraint Jacobian is singular or nearly so" run --model four-bar --lengths 1,3,1,3 --torque 5 \
  --time 3 --steps 3000 -o out.csv
grep -q "the constraint Jacobian is singular or nearly so" stderr.txt &&
  [ "$(wc -l < out.csv.part)" -gt 1000 ] && ok ||
  bad "four-bar change point: $(cat stderr.txt)"
rm -f out.csv.part out.csv.ckpt
# Starting on the change point is refused (exit 2), naming the singular Jacobian.
expect_error 2 "four-bar starts collinear" "four-bar: the constraint Jacobian is singular at the" run --model four-bar --lengths 1,3,1,3 --q0 0 -o out.csv
grep -q "constraint Jacobian is singular at the initial state" stderr.txt &&
  ! grep -q -- '--project' stderr.txt && ok ||
  bad "four-bar collinear start: $(cat stderr.txt)"

# --- typed constraints: --lagrangian with --constraints ----------------------------------------
# A point mass on a unit rod in Cartesian coordinates (g = 1: omega = 1) from (0.6, -0.8) at rest,
# against the pendulum model's exact angle from atan2(0.6, 0.8) = 0.64350110879328437. Simpson at
# h = 0.01 over 10 s: measured 6.7e-11 (4.2e-12 at h/2: order 4); bound 1e-9. Residuals at round-off.
rod=(--model lagrangian --lagrangian "0.5*(x_dot**2+y_dot**2) - y" --coordinates x,y
  --constraints "x**2+y**2-1")
"$VARSYM" run "${rod[@]}" --q0 0.6,-0.8 --time 10 --steps 1000 -o rod.csv 2> rod.log &&
  "$VARSYM" run --model pendulum --omega 1 --q0 0.64350110879328437 --time 10 --steps 1000 \
    -o pend.csv 2> /dev/null && head -1 rod.csv | grep -q "constraint_residual,hidden_residual,lambda_1$" &&
  paste -d, rod.csv pend.csv | awk -F, 'NR > 1 { d = atan2($3, -$4) - $18; if (d < 0) d = -d
    if (d > m) m = d; n++ } END { exit !(n == 1001 && m <= 1e-9 && m > 0) }' &&
  le "$(max_abs rod.csv 10)" 1e-14 && le "$(max_abs rod.csv 11)" 1e-14 && le "$(max_abs rod.csv 9)" 1e-10 &&
  ok || bad "typed rod against the exact pendulum: $(cat rod.log; tail -1 rod.csv)"
# Off the rod: refused before anything is written, pointing to --project, which moves it there.
expect_error 2 "typed constraints: start off the rod" "lagrangian: the initial position is off the constraints" run "${rod[@]}" --q0 1,-1 -o off.csv
grep -q -- "--project" stderr.txt && [ ! -e off.csv ] && ok || bad "off the rod: $(cat stderr.txt)"
"$VARSYM" run "${rod[@]}" --q0 1,-1 --project --time 1 --steps 10 -o proj.csv 2> /dev/null &&
  awk -F, 'NR == 2 { r = $3 * $3 + $4 * $4 - 1; exit !(r < 1e-15 && r > -1e-15) }' proj.csv && ok ||
  bad "--project: $(head -2 proj.csv)"
expect_error 2 "--project without --constraints" "--project moves the start onto the constraints: it needs" run --lagrangian "0.5*x_dot**2" --coordinates x \
  --project -o out.csv
expect_error 2 "a constraint on a velocity" "--constraints: constraint 1 (x*y_dot) depends on the" run "${rod[@]/x\*\*2+y\*\*2-1/x*y_dot}" -o out.csv
grep -q "depends on the velocity y_dot" stderr.txt && ok || bad "velocity constraint: $(cat stderr.txt)"
expect_error 2 "typed constraints: no sections" "varsym section needs a stepper with dense output" section "${rod[@]}" --grid q0_1=0.6:0.8:2 \
  --q0 0.6,-0.8 --plane q1=0 -o sec.csv
# Ensembles: the members off the rod are invalid (named), or projected with --set project=1.
"$VARSYM" ensemble "${rod[@]}" --grid q0_1=0.6:0.8:3 --q0 0.6,-0.8 -o rens.csv 2> /dev/null &&
  "$VARSYM" ensemble "${rod[@]}" --grid q0_1=0.6:0.8:3 --q0 0.6,-0.8 --set project=1 \
    -o rensp.csv 2> /dev/null &&
  [ "$(grep -c ',invalid,.*off the constraints' rens.csv)" = 2 ] &&
  [ "$(grep -c ',completed,' rensp.csv)" = 3 ] && ok ||
  bad "typed constraints ensemble: $(cat rens.csv rensp.csv)"
# converge: Simpson's fitted order 4 against gauss-8.
"$VARSYM" converge "${rod[@]}" --set q0_1=0.6 --set q0_2=-0.8 --steps 50,100,200 > rconv.txt &&
  awk '$1 == "fitted" { f = 1; exit !($3 > 3.7 && $3 < 4.3) } END { if (!f) exit 1 }' rconv.txt &&
  ok || bad "typed constraints converge: $(cat rconv.txt)"

finish
