#!/usr/bin/env bash
# tests/cli/rigid_test.sh VARSYM: the rigid bodies of `varsym run` (rigid-body, top, pendulum-3d)
# end to end: their columns, what each conserves (to round-off, read back from the CSV), the
# closed forms they are compared with, the conventions of --q0, the top through the vertical
# where the Euler-angle heavy-top refuses, resume after SIGKILL, and bad input.
source "$(dirname "$0")/lib.sh" "$@"

# col FILE NAME: the column number of NAME in FILE's header.
col() { head -1 "$1" | tr ',' '\n' | grep -nx "$2" | cut -d: -f1; }
# spread FILE NAME: max - min of column NAME, relative to max |value| (0 if all are 0); nothing
# (which lt refuses) without a data row or without the column. (The conditional is in
# parentheses: unbracketed, awk read "printf ..., m > 0 ? ..." as output redirected to a file
# named 0, printed nothing, and every check of a spread passed on the empty string.)
spread() {
  awk -F, -v c="$(col "$1" "$2")" 'NR > 1 && c != "" { v = $c + 0; if (NR == 2 || v < lo) lo = v;
    if (NR == 2 || v > hi) hi = v; a = v < 0 ? -v : v; if (a > m) m = a }
    END { if (NR > 1 && c != "") printf "%.3e", (m > 0 ? (hi - lo) / m : 0) }' "$1"
}
# maxabs FILE NAME [OTHER]: max |NAME| (or max |NAME - OTHER|) over the rows; nothing without a
# data row or a column.
maxabs() {
  awk -F, -v c="$(col "$1" "$2")" -v d="${3:+$(col "$1" "${3:-}")}" -v o="${3:-}" 'NR > 1 {
    v = $c - (d != "" ? $d : 0); if (v < 0) v = -v; if (v > m) m = v }
    END { if (NR > 1 && c != "" && (o == "" || d != "")) printf "%.3e", m }' "$1"
}

"$VARSYM" models > models.txt && for m in rigid-body top pendulum-3d; do
  grep -q "^$m: " models.txt && ok || bad "models does not list $m"
done

# --- the symmetric top: columns, momentum maps, closed-form nutation ---------------------------
"$VARSYM" run --model top --periods 3 -o top.csv || bad "top run failed"
[ "$(head -1 top.csv)" = "step,t,q_w,q_x,q_y,q_z,Omega_1,Omega_2,Omega_3,energy,L_z,Pi_3,theta,theta_exact,orthogonality" ] &&
  ok || bad "top header: $(head -1 top.csv)"
[ "$(wc -l < top.csv)" -eq 302 ] && ok || bad "top: 3 periods of 100 steps: $(wc -l < top.csv) lines"
# L_z = 2.588 and Pi_3 = 4.135 kg m^2/s: conserved to round-off (a few ulps of the value).
s=$(spread top.csv L_z); lt "$s" 1e-14 && ok || bad "top L_z varies by $s"
s=$(spread top.csv Pi_3); lt "$s" 1e-14 && ok || bad "top Pi_3 varies by $s"
s=$(maxabs top.csv orthogonality); lt "$s" 1e-15 && ok || bad "top |R^T R - I| up to $s"
# Order 4 at 100 steps per nutation period: theta within 2e-4 rad of the closed form (measured
# 7.1e-5); order 2 at the same step is worse by more than 10 (the negative control).
e4=$(maxabs top.csv theta theta_exact); lt "$e4" 2e-4 && ok || bad "top theta error $e4"
"$VARSYM" run --model top --periods 3 --order 2 -o top2.csv || bad "order-2 top failed"
e2=$(maxabs top2.csv theta theta_exact)
numbers "order 2 against 4" "$e4" && lt "$(awk -v a="$e4" 'BEGIN { print 10 * a }')" "$e2" && ok || bad "order 2 ($e2) not worse than 4 ($e4)"
s=$(spread top.csv energy); lt "$s" 1e-6 && ok || bad "top energy varies by $s"

# --- through the vertical: the group model runs, the Euler-angle model refuses ----------------
expect_error 2 "heavy-top at the vertical" "heavy-top: the mass matrix d2L/dqdot2 is singular or not" run --model heavy-top --q0 0,0,0 --v0 0.3,0,5 -o out.csv
"$VARSYM" run --model top --q0 0,0,0 --v0 0.3,0,5 --time 10 --steps 2000 -o vert.csv ||
  bad "top through the vertical failed"
grep -q theta_exact vert.csv && bad "a closed form where the axis reaches the vertical" || ok
s=$(awk -F, -v c="$(col vert.csv theta)" 'NR > 2 && $c < 1e-3 { n++ } END { print n + 0 }' vert.csv)
[ "$s" -ge 2 ] && ok || bad "the axis did not come back to the vertical ($s rows with theta < 1e-3)"
s=$(spread vert.csv L_z); lt "$s" 1e-14 && ok || bad "vertical top L_z varies by $s"

# --- an iteration or predictor the Lie group integrator does not have is refused, not ignored -
for m in rigid-body top pendulum-3d; do
  expect_error 2 "$m --iteration simplified" "Lie group integrator solves each step by Newton" \
    run --model $m --iteration simplified -o out.csv
  expect_error 2 "$m --predictor previous" "use the predictor taylor" \
    run --model $m --predictor previous -o out.csv
done
"$VARSYM" run --model top --iteration newton --time 0.1 --steps 100 -o newton.csv && ok ||
  bad "top --iteration newton (what it does) was refused"

# --- the free body: spatial momentum, Casimir, the symmetric body's closed form ---------------
"$VARSYM" run --model rigid-body --every 100 -o free.csv || bad "rigid-body run failed"
for c in L_x L_y L_z Pi_norm; do
  s=$(spread free.csv $c); lt "$s" 1e-13 && ok || bad "rigid-body $c varies by $s"
done
# The default start turns near the intermediate axis: Omega_2 changes sign (the body flips).
awk -F, 'NR > 1 && $8 < -0.5 { f = 1 } END { exit !f }' free.csv && ok || bad "rigid-body did not flip"
"$VARSYM" run --model rigid-body --inertia 1,1,0.5 --v0 0.3,-0.5,4 --periods 2 \
  --steps-per-period 400 -o sym.csv &&
  grep -q attitude_error sym.csv && ok || bad "symmetric free body: no attitude_error column"
# Order 4 at 400 steps per period of Pi: measured 1.02e-5 rad (2.73e-3 at 100: 256 = 4^4 times).
e=$(maxabs sym.csv attitude_error); lt "$e" 3e-5 && ok || bad "symmetric free body error $e rad"

# --- the 3-D pendulum, conventions of --q0 and --matrix --------------------------------------
"$VARSYM" run --model pendulum-3d --every 100 --matrix -o p3.csv || bad "pendulum-3d failed"
[ "$(head -1 p3.csv | tr ',' '\n' | wc -l)" -eq 22 ] && ok || bad "pendulum-3d --matrix columns"
s=$(spread p3.csv energy); lt "$s" 1e-4 && ok || bad "pendulum-3d energy varies by $s"
# R_33 = 1 - 2(q_x^2 + q_y^2) and R_21 = 2(q_x q_y + q_w q_z) in every row.
awk -F, 'NR > 1 { a = $22 - (1 - 2 * ($4 * $4 + $5 * $5)); b = $17 - 2 * ($4 * $5 + $3 * $6);
  if (a * a + b * b > 1e-28) bad = 1 } END { exit bad }' p3.csv && ok || bad "quaternion and matrix disagree"
# Euler angles (1, 0, 0) and the quaternion (cos 1/2, sin 1/2, 0, 0) are the same attitude.
"$VARSYM" run --model top --q0 1,0,0 --time 1 --steps 100 -o e.csv &&
  "$VARSYM" run --model top --q0 0.87758256189037276,0.47942553860420295,0,0 --time 1 --steps 100 -o q.csv ||
  bad "--q0 as Euler angles or quaternion failed"
d=$(paste -d, e.csv q.csv | awk -F, 'NR > 1 { for (i = 3; i <= 15; i++) { v = $i - $(i + 15);
  if (v < 0) v = -v; if (v > m) m = v } } END { printf "%.3e", m }')
lt "$d" 1e-12 && ok || bad "Euler-angle and quaternion starts differ by $d"

# Six inertia entries J11,J22,J33,J12,J13,J23: with zero products of inertia, the same run.
"$VARSYM" run --model top --periods 1 --inertia 1,1,0.5,0,0,0 -o six.csv &&
  "$VARSYM" run --model top --periods 1 --inertia 1,1,0.5 -o three.csv && cmp -s six.csv three.csv &&
  ok || bad "--inertia with 6 entries differs from its 3 principal moments"

# --- SIGKILL and resume: byte-identical ---------------------------------------------------------
"$VARSYM" run --model top --periods 1500 --every 10 -o ref.csv || bad "reference run failed"
"$VARSYM" run --model top --periods 1500 --every 10 -o k.csv --checkpoint k.ckpt --checkpoint-every 5000 &
pid=$!
for _ in $(seq 100); do [ -e k.ckpt ] && break; sleep 0.02; done
kill -9 "$pid" 2> /dev/null
wait "$pid" 2> /dev/null
[ -e k.ckpt ] && "$VARSYM" run --resume k.ckpt 2> /dev/null && cmp -s k.csv ref.csv && ok ||
  bad "top resumed after SIGKILL differs from the uninterrupted run"

# --- ensembles and converge: the same model, from the models layer ---------------------------
# Two members over the weight: member 0 (the default weight) ends at the run's last tilt to
# round-off (one stepper, two drivers); member 1 elsewhere (the negative control). No tangent
# map: lambda and MEGNO are nan.
"$VARSYM" ensemble --model top --grid weight=1:2:2 --time 1 --steps 100 -o ens.csv 2> err.txt &&
  "$VARSYM" run --model top --time 1 --steps 100 -o run.csv || bad "top ensemble: $(cat err.txt)"
a=$(tail -1 run.csv | cut -d, -f"$(col run.csv theta)")
b=$(awk -F, -v c="$(col ens.csv q_1)" 'NR == 2 { print $c }' ens.csv)
c=$(awk -F, -v c="$(col ens.csv q_1)" 'NR == 3 { print $c }' ens.csv)
numbers "top ensemble tilt" "$a" "$b" "$c" && awk -v a="$a" -v b="$b" -v c="$c" 'BEGIN { e = a - b; f = a - c; e = e < 0 ? -e : e;
  f = f < 0 ? -f : f; exit !(e < 1e-13 && f > 1e-3) }' && ok ||
  bad "top ensemble tilt: run $a, members $b $c"
[ "$(awk -F, -v c="$(col ens.csv lyapunov)" 'NR > 1 { print $c }' ens.csv | sort -u)" = nan ] &&
  ok || bad "a rigid body's lambda is not nan: $(cat ens.csv)"
# converge: lgvi of --set order, against lgvi-6: observed orders 2 and 4 on the 3-D pendulum.
for k in 2 4; do
  "$VARSYM" converge --model pendulum-3d --set order=$k --time 1 --steps 100,200,400,800 > c.txt &&
    awk -v k=$k '$1 == "fitted" { exit !($2 > k - 0.1 && $2 < k + 0.1) }' c.txt &&
    grep -q "lgvi-$k (order $k) on pendulum-3d" c.txt && ok || bad "converge order $k: $(cat c.txt)"
done
expect_error 2 "converge --scheme for a rigid body" "--scheme and --degree do not apply to --model top: rigid" converge --model top --scheme gauss
expect_error 2 "section of a rigid body" "varsym section needs a stepper with dense output" section --model top --plane q1=1 -o out.csv

# --- bad input ---------------------------------------------------------------------------------
expect_error 2 "scheme for a rigid body" "--scheme and --degree do not apply to --model top: rigid" run --model top --scheme gauss -o out.csv
expect_error 2 "degree for a rigid body" "--degree applies to --scheme lobatto or gauss; simpson has" run --model rigid-body --degree 3 -o out.csv
expect_error 2 "order 3" "top: order must be 2, 4 or 6, got 3" run --model top --order 3 -o out.csv
expect_error 2 "impossible inertia" "rigid-body: the principal moments of inertia must satisfy" run --model rigid-body --inertia 1,1,3 -o out.csv
expect_error 2 "negative inertia" "top: the inertia tensor must be positive definite" run --model top --inertia 1,-1,1 -o out.csv
expect_error 2 "inertia of 2 values" "top: inertia needs 3 values (principal moments I1,I2,I3) or" run --model top --inertia 1,1 -o out.csv
expect_error 2 "inertia not positive definite" "top: the inertia tensor must be positive definite" run --model top --inertia 1,1,1,2,0,0 -o out.csv
expect_error 2 "com for a free body" "--com is a parameter of --model top, not of --model rigid-body" run --model rigid-body --com 0,0,1 -o out.csv
expect_error 2 "com of 2 values" "top: com needs 3 values (x,y,z of the centre of mass), got 2" run --model top --com 0,1 -o out.csv
expect_error 2 "negative weight" "--weight: weight must be non-negative, got -1" run --model top --weight -1 -o out.csv
expect_error 2 "non-unit quaternion" "top: q0: a quaternion (w,x,y,z) must have norm 1, got" run --model top --q0 1,0,0,0.1 -o out.csv
expect_error 2 "q0 of 5 values" "top: q0 needs 3 values (th, phi, psi) or 4" run --model top --q0 1,0,0,0,0 -o out.csv
expect_error 2 "v0 of 2 values" "top: v0 needs 3 values (th, phi, psi) or 4" run --model top --v0 1,0 -o out.csv
expect_error 2 "p0 and v0" "--p0 excludes --v0" run --model top --p0 0,0,1 --v0 0,0,1 -o out.csv
expect_error 2 "NaN com" "--com: com must be a finite number, got nan" run --model top --com 0,0,nan -o out.csv
expect_error 2 "infinite initial energy" "top: the energy of the initial state is not a finite number" run --model top --v0 1e300,0,0 -o out.csv
# A turn of more than 90 degrees per sub-step has no step: exit 3, the step limit in the message.
rm -f big.csv*
"$VARSYM" run --model top --time 10 --steps 100 -o big.csv 2> big.txt
[ $? -eq 3 ] && grep -q "lgvi-4's step limit" big.txt && [ -e big.csv.part ] && ok ||
  bad "too large a step: $(cat big.txt)"

finish
