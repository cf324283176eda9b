#!/usr/bin/env bash
# tests/cli/optimize_systems_test.sh VARSYM: `varsym optimize` on systems known at run time, all
# through the one compiled transcription: a URDF robot (--urdf), a typed Lagrangian
# (--lagrangian --inputs, and --constraints) and the arm (--model arm). The references are independent: one
# pendulum written three ways (a one-joint URDF through the recursive multibody derivatives, a
# typed L through symbolic ones, the built-in model through automatic ones) must reach the same
# optimum; a 7-joint robot's optimum must agree between two schemes of different order, keep
# its URDF torque and joint limits, and pass the replay through the simulator (closure). Bad
# input: an input that is not a coordinate, a target outside the joint limits, a robot with no
# actuated joint, and an infeasible bound (exit 3, last iterate kept). Task-space ends (--reach):
# the UR5's tool sent to the pose its joint-space optimum ends at must reproduce that optimum
# (six joints, a full pose: the end joints are fixed by it); a target out of reach exits 3.
data=$(realpath "$(dirname "$0")/../data/urdf")
source "$(dirname "$0")/lib.sh" "$@"
pi=3.141592653589793
cost_of() { sed -n 's/^varsym optimize: solved .*: cost \([^,]*\), T.*/\1/p' "$1"; }
closure_of() { sed -n 's/.*closure (general engine replay) \([^ ]*\)$/\1/p' "$1"; }

# One pendulum three ways: L = 0.135 th'^2 + 4.905 cos th (tests/data/urdf/pendulum.urdf), a
# swing-up in 3 s. The three derivative codes differ; the discrete problem is the same, so the
# optima agree to IPOPT's tolerance (1e-10 measured to 12 digits).
"$VARSYM" optimize --urdf "$data/pendulum.urdf" --time 3 --steps 40 --from 0 --to $pi \
  --quiet -o urdf.csv 2> urdf.err && ok || bad "URDF pendulum: $(tail -1 urdf.err)"
"$VARSYM" optimize --lagrangian "0.135*th_dot**2 + 4.905*cos(th)" --coordinates th --inputs th \
  --time 3 --steps 40 --from 0 --to $pi --quiet -o typed.csv 2> typed.err && ok ||
  bad "typed pendulum: $(tail -1 typed.err)"
omega=$(awk 'BEGIN { printf "%.17g", sqrt(4.905 / 0.27) }')
"$VARSYM" optimize --model pendulum --mass 0.27 --omega "$omega" --time 3 --steps 40 --from 0 \
  --to $pi --quiet -o model.csv 2> model.err && ok || bad "built-in pendulum: $(tail -1 model.err)"
c_urdf=$(cost_of urdf.err) c_typed=$(cost_of typed.err) c_model=$(cost_of model.err)
rel "$c_urdf" "$c_model" 1e-9 && rel "$c_typed" "$c_model" 1e-9 && ok ||
  bad "the three pendulums' optima differ: $c_urdf (URDF) $c_typed (typed) $c_model (model)"
# Negative control: another Lagrangian (twice the gravity) has another optimum.
"$VARSYM" optimize --lagrangian "0.135*th_dot**2 + 9.81*cos(th)" --coordinates th --inputs th \
  --time 3 --steps 40 --from 0 --to $pi --quiet -o heavy.csv 2> heavy.err && ok ||
  bad "twice the gravity: $(tail -1 heavy.err)"
rel "$(cost_of heavy.err)" "$c_model" 1e-3 && bad "twice the gravity, the same optimum" || ok
# The typed L's parameters are the model's: the same L with g given as a parameter.
"$VARSYM" optimize --lagrangian "0.5*I*th_dot**2 + m*g*l*cos(th)" --parameters I=0.27,m=1,g=9.81,l=0.5 \
  --coordinates th --inputs th --time 3 --steps 40 --from 0 --to $pi --quiet -o par.csv 2> par.err
rel "$(cost_of par.err)" "$c_model" 1e-9 && ok || bad "typed L with parameters: $(tail -1 par.err)"

# The arm with one link and no damping is the point-mass pendulum: L = m l^2 th'^2/2 + m g l cos th.
"$VARSYM" optimize --model arm --masses 2 --lengths 1.5 --damping 0 --time 3 --steps 40 \
  --from 0 --to $pi --quiet -o arm1.csv 2> arm1.err && ok || bad "one-link arm: $(tail -1 arm1.err)"
"$VARSYM" optimize --lagrangian "0.5*2*1.5**2*th_dot**2 + 2*9.81*1.5*cos(th)" --coordinates th \
  --inputs th --time 3 --steps 40 --from 0 --to $pi --quiet -o arm1t.csv 2> arm1t.err
rel "$(cost_of arm1.err)" "$(cost_of arm1t.err)" 1e-9 && ok ||
  bad "one-link arm $(cost_of arm1.err) against its typed L $(cost_of arm1t.err)"
# The three-link arm with its joint damping (0.5 N m s/rad each) in the replay too.
"$VARSYM" optimize --model arm --time 2 --steps 40 --from 0,0,0 --to 0.8,0.5,0.3 --quiet \
  -o arm.csv --controls arm_u.csv 2> arm.err && ok || bad "arm: $(tail -1 arm.err)"
le "$(closure_of arm.err)" 1e-8 && ok || bad "arm closure $(closure_of arm.err)"
[ "$(head -1 arm_u.csv)" = "t,u1,u2,u3" ] && ok || bad "arm controls: $(head -1 arm_u.csv)"
expect_error 2 "a controller gain in optimize" "--kp is a simulation's parameter of arm; optimize computes" optimize --model arm --kp 1,1,1 --time 2 \
  --steps 10 --from 0,0,0 --to 1,1,1 -o out.csv
grep -q "kp is a simulation's parameter of arm" stderr.txt && ok || bad "$(cat stderr.txt)"

# A 7-joint robot (KUKA iiwa 14) rest to rest in 2 s. The transcription's accuracy, without the
# limits (a smooth optimum): Simpson and gauss-2 (both order 4, other quadratures and
# polynomials) at N = 80 agree with gauss-2 at N = 160 to 1e-4 (measured 8e-5 and 2e-5; the
# optimum 220.098). Negative control: Simpson at N = 40 is 1e-3 away. That optimum spins the
# wrist at up to 13 rad/s; within the URDF limits (the efforts 320 320 176 176 110 40 40 N m,
# the joints' ranges and their velocity limits) the torques, q and the node velocities stay
# inside, a velocity limit binds, and the replay closes.
iiwa="$data/iiwa14_no_collision.urdf"
to=0.4,0.3,0.2,-0.3,0.2,0.3,0.2
"$VARSYM" optimize --urdf "$iiwa" --no-limits --time 2 --steps 80 --from 0,0,0,0,0,0,0 --to $to \
  --quiet -o free80.csv 2> free80.err && ok || bad "iiwa: $(tail -1 free80.err)"
for n in 80 160; do
  "$VARSYM" optimize --urdf "$iiwa" --no-limits --time 2 --steps $n --scheme gauss --degree 2 \
    --from 0,0,0,0,0,0,0 --to $to --quiet -o iiwa_g$n.csv 2> iiwa_g$n.err && ok ||
    bad "iiwa gauss-2 N = $n: $(tail -1 iiwa_g$n.err)"
done
"$VARSYM" optimize --urdf "$iiwa" --no-limits --time 2 --steps 40 --from 0,0,0,0,0,0,0 --to $to \
  --quiet -o iiwa40.csv 2> iiwa40.err && ok || bad "iiwa N = 40: $(tail -1 iiwa40.err)"
fine=$(cost_of iiwa_g160.err)
rel "$(cost_of free80.err)" "$fine" 1e-4 && rel "$(cost_of iiwa_g80.err)" "$fine" 1e-4 && ok ||
  bad "iiwa: Simpson $(cost_of free80.err), gauss-2 $(cost_of iiwa_g80.err) at N = 80, $fine at 160"
rel "$(cost_of iiwa40.err)" "$fine" 1e-4 && bad "iiwa: N = 40 as close as N = 80" || ok
# The steps' derivatives on 1 and on 3 threads (the run above: every CPU) give the same nodes
# and controls to the byte (docs/optimal_control.md, "Threads in the derivatives"); the
# negative control, Simpson's nodes at the same N, differ.
for t in 1 3; do
  "$VARSYM" optimize --urdf "$iiwa" --no-limits --time 2 --steps 80 --scheme gauss --degree 2 \
    --from 0,0,0,0,0,0,0 --to $to --threads $t --quiet -o iiwa_t$t.csv --controls iiwa_u$t.csv \
    2> iiwa_t$t.err && ok || bad "iiwa --threads $t: $(tail -1 iiwa_t$t.err)"
done
"$VARSYM" optimize --urdf "$iiwa" --no-limits --time 2 --steps 80 --scheme gauss --degree 2 \
  --from 0,0,0,0,0,0,0 --to $to --quiet -o iiwa_t0.csv --controls iiwa_u0.csv 2> /dev/null
cmp -s iiwa_t1.csv iiwa_t3.csv && cmp -s iiwa_t1.csv iiwa_t0.csv &&
  cmp -s iiwa_u1.csv iiwa_u3.csv && cmp -s iiwa_u1.csv iiwa_u0.csv && ok ||
  bad "--threads changed the answer"
[ -s iiwa_t1.csv ] && ! cmp -s iiwa_t1.csv free80.csv && ok || bad "the negative control"
expect_error 2 "negative --threads" "--threads" optimize --urdf "$iiwa" --time 2 --from 0,0,0,0,0,0,0 --to $to --threads -1 -o out.csv
# Minimum time within the URDF limits, without --max-control: the efforts bound the torques (an
# unbounded input is refused), solved, faster than the 2 s guess (0.567 s: the velocity limits
# bind), the torques within the efforts (320 320 176 176 110 40 40 N m). Negative control:
# --no-limits leaves the torques unbounded, refused.
"$VARSYM" optimize --urdf "$iiwa" --time 2 --steps 25 --from 0,0,0,0,0,0,0 --to $to \
  --cost time,effort=0.001 --quiet -o fast.csv --controls fast_u.csv 2> fast.err && ok ||
  bad "iiwa in minimum time: $(tail -1 fast.err)"
lt "$(tail -1 fast.csv | cut -d, -f1)" 1 && ok || bad "iiwa minimum time: T = $(tail -1 fast.csv | cut -d, -f1)"
awk -F, 'NR > 1 { split("320 320 176 176 110 40 40", e, " ")
  for (j = 1; j <= 7; ++j) { a = $(j + 1) < 0 ? -$(j + 1) : $(j + 1)
    if (a > e[j] * (1 + 1e-9)) over = 1 } }
  END { exit !(NR > 1 && !over) }' fast_u.csv && ok || bad "iiwa minimum time: torques"
expect_error 2 "minimum time without limits" "--cost time needs --max-control" optimize --urdf "$iiwa" --no-limits --time 2 --from 0,0,0,0,0,0,0 --to $to --cost time -o out.csv
"$VARSYM" optimize --urdf "$iiwa" --time 2 --steps 80 --from 0,0,0,0,0,0,0 --to $to --quiet \
  -o iiwa.csv --controls iiwa_u.csv 2> iiwa.err && ok || bad "iiwa: $(tail -1 iiwa.err)"
le "$(closure_of iiwa.err)" 1e-8 && ok ||
  bad "iiwa closure $(closure_of iiwa.err)"
awk -F, 'BEGIN { split("320 320 176 176 110 40 40", e, " ") }
  NR > 1 { for (i = 2; i <= 8; ++i) if ($i > e[i - 1] + 1e-6 || $i < -e[i - 1] - 1e-6) exit 1 }' \
  iiwa_u.csv && ok || bad "iiwa: a torque beyond its URDF effort"
awk -F, 'BEGIN { split("2.96705972839 2.09439510239 2.96705972839 2.09439510239 2.96705972839 2.09439510239 3.05432619099", l, " ") }
  NR > 1 { for (i = 2; i <= 8; ++i) if ($i > l[i - 1] + 1e-9 || $i < -l[i - 1] - 1e-9) exit 1 }' \
  iiwa.csv && ok || bad "iiwa: a joint beyond its URDF limits"
# The node velocities (columns v1..v7) within the velocity limits, exactly (they are unknowns of
# the problem, bounded); the largest |v|/limit is 1: a limit binds. Without the limits it is
# above 5.
vmax() { awk -F, 'BEGIN { split("1.4835298641951802 1.4835298641951802 1.7453292519943295 1.3089969389957472 2.2689280275926285 2.356194490192345 2.356194490192345", l, " ") }
  NR > 1 { for (i = 9; i <= 15; ++i) { a = ($i < 0 ? -$i : $i) / l[i - 8]; if (a > m) m = a } } END { if (NR > 1) printf "%.12f\n", m }' "$1"; }
lt 0.999 "$(vmax iiwa.csv)" && le "$(vmax iiwa.csv)" 1.000000001 && ok ||
  bad "iiwa: largest |v|/limit $(vmax iiwa.csv), not 1"
grep -q "node velocities exceed" iiwa.err && bad "iiwa: a velocity excess reported: $(cat iiwa.err)" || ok
lt 5 "$(vmax free80.csv)" && ok ||
  bad "iiwa without limits: largest |v|/limit $(vmax free80.csv)"
[ "$(head -1 iiwa.csv | cut -d, -f1-3)" = "t,q1,q2" ] && ok || bad "iiwa header $(head -1 iiwa.csv)"

# --max-velocity against an exact optimum: the double integrator (L = x'^2/2, u the force) from
# rest at 0 to rest at 1 in T = 2 with |x'| <= V = 0.6 and the effort cost. Unbounded, the
# optimum peaks at 1.5/T = 0.75 (cost 6/T^3 = 0.75); bounded, it accelerates with u = a (t1 - t)
# until x' = V at t1, coasts, and brakes symmetrically: a t1^2/2 = V and 1 = V (T - 2 t1/3), so
# t1 = 1.5 (T - 1/V) = 0.5 and the cost is 4 V^2/(3 t1) = 0.96. The optimum is piecewise cubic
# with its junctions on nodes at N = 40: Simpson gives 0.96000000058.
"$VARSYM" optimize --lagrangian "0.5*x_dot**2" --coordinates x --inputs x --time 2 --steps 40 \
  --from 0 --to 1 --max-velocity 0.6 --quiet -o di.csv 2> di.err && ok || bad "$(tail -1 di.err)"
rel "$(cost_of di.err)" 0.96 1e-8 && ok || bad "bounded double integrator: $(cost_of di.err), not 0.96"
"$VARSYM" optimize --lagrangian "0.5*x_dot**2" --coordinates x --inputs x --time 2 --steps 160 \
  --from 0 --to 1 --quiet -o di.csv 2> di.err && ok || bad "$(tail -1 di.err)"
rel "$(cost_of di.err)" 0.75 1e-6 && ok || bad "free double integrator: $(cost_of di.err), not 0.75"

# --constraints on a typed L: a unit mass on the unit circle (Cartesian x, y; g(q) = x^2 + y^2 - 1)
# pushed horizontally, from hanging to horizontal at rest in 2 s. Every node must be on the
# circle, and the constrained engine's replay must retrace the motion (the closure). The same
# optimum against the same system written in C++ (automatic derivatives) is in
# tests/models/test_optimal_typed.cpp. Negative control: without the constraint nothing holds
# the mass up (no input on y), and no motion reaches the target: infeasible, exit 3.
circle=(--lagrangian "0.5*(x_dot**2 + y_dot**2) - g*y" --coordinates x,y --parameters g=9.81
  --inputs x --time 2 --steps 40 --from 0,-1 --to 1,0)
"$VARSYM" optimize "${circle[@]}" --constraints "x**2 + y**2 - 1" --quiet -o circle.csv \
  2> circle.err && ok || bad "typed constraints: $(tail -1 circle.err)"
awk -F, 'NR > 1 { r = $2 * $2 + $3 * $3 - 1; if (r > 1e-10 || r < -1e-10) bad = 1 }
  END { exit bad || NR != 42 }' circle.csv && ok || bad "typed constraints: a node off the circle"
lt "$(closure_of circle.err)" 1e-9 && ok ||
  bad "typed constraints: closure $(closure_of circle.err)"
"$VARSYM" optimize "${circle[@]}" --quiet -o free.csv 2> free.err
rc=$?
[ $rc -eq 3 ] && ok || bad "without the constraint: exit $rc, not 3 ($(tail -1 free.err))"
expect_error 2 "a constraint on a velocity" "--constraints: constraint 1 (x**2 + y_dot - 1) depends on" optimize "${circle[@]}" --constraints "x**2 + y_dot - 1" \
  -o out.csv
grep -q "^varsym: error: --constraints: " stderr.txt && ok || bad "$(cat stderr.txt)"
expect_error 2 "--constraints without --lagrangian" "--constraints: --coordinates, --parameters, --inputs and" optimize --model pendulum --time 1 --from 0 \
  --to 1 --constraints "q - 1" -o out.csv
grep -q "need --lagrangian" stderr.txt && ok || bad "$(cat stderr.txt)"

# --reach: the UR5 tool's pose at the joint problem's end, reached from a guess near it: the
# same optimum to IPOPT's tolerance, and the same end joints.
ur5="$data/ur5_robot.urdf" from=0,-1.57,0,-1.57,0,0 to=0.5,-1.2,0.6,-1.4,0.4,0.3
"$VARSYM" optimize --urdf "$ur5" --time 2 --steps 20 --from $from --to $to --quiet -o ur5.csv   2> ur5.err && ok || bad "UR5 joint problem: $(tail -1 ur5.err)"
# The tool0 pose at $to, written out from varsym.Robot("ur5_robot.urdf").pose("tool0", to)
# (origin; URDF rpy of the rotation).
"$VARSYM" optimize --urdf "$ur5" --time 2 --steps 20 --from $from --to 0.55,-1.15,0.65,-1.35,0.45,0.35 \
  --reach tool0 --reach-position 0.39440959558325767,0.42622012884336685,0.7752871108593365 \
  --reach-rpy=-0.40083057488798507,1.1760435746093676,1.8145789926529627 --quiet -o ur5r.csv \
  2> ur5r.err && ok || bad "UR5 reach: $(tail -1 ur5r.err)"
rel "$(cost_of ur5r.err)" "$(cost_of ur5.err)" 1e-7 && ok ||
  bad "UR5: reach optimum $(cost_of ur5r.err), joint optimum $(cost_of ur5.err)"
grep -q "^varsym optimize: tool0 ends [0-9.e-]* m and [0-9.e-]* rad from its target" ur5r.err && ok ||
  bad "UR5 reach: no miss line: $(cat ur5r.err)"
awk -F, -v to="$to" 'BEGIN { split(to, q, ",") } END { for (i = 2; i <= 7; ++i) { d = $i - q[i - 1];
  if (d > 1e-6 || d < -1e-6) exit 1 } }' ur5r.csv && ok || bad "UR5 reach: end joints $(tail -1 ur5r.csv | cut -d, -f2-7)"
# Out of reach: 2 m in front of the iiwa (its flange reaches about 1.3 m): exit 3, files kept.
"$VARSYM" optimize --urdf "$data/iiwa14_no_collision.urdf" --time 2 --steps 20 --from 0,0,0,0,0,0,0 \
  --reach iiwa_link_ee --reach-position 2,0,1 --quiet -o far.csv 2> far.err
rc=$?
[ $rc -eq 3 ] && grep -q "infeasible" far.err && ok || bad "out of reach: exit $rc ($(tail -1 far.err))"
[ "$(wc -l < far.csv)" -eq 22 ] && ok || bad "out of reach: the last iterate was not kept"
expect_error 2 "--reach without a robot" "--reach needs a robot (--urdf FILE): it names one of its" optimize --model pendulum --time 1 --from 0 --reach x \
  --reach-position 0,0,1 -o out.csv
grep -q "needs a robot" stderr.txt && ok || bad "$(cat stderr.txt)"
expect_error 2 "an unknown link" "--reach: no link 'hand' in ur5" optimize --urdf "$ur5" --time 1 --from $from --reach hand \
  --reach-position 0,0,1 -o out.csv
grep -q "no link 'hand' in ur5 (its links: " stderr.txt && ok || bad "$(cat stderr.txt)"
expect_error 2 "--reach without a position" "--reach needs --reach-position X,Y,Z: where the link's" optimize --urdf "$ur5" --time 1 --from $from \
  --reach tool0 -o out.csv
expect_error 2 "no --to and no --reach" "optimize needs --to (the final joint positions) or --reach" optimize --urdf "$ur5" --time 1 --from $from -o out.csv

# Bad input.
expect_error 2 "an input that is not a coordinate" "--lagrangian: the input 'y' is not a coordinate; the" optimize --lagrangian "0.5*x_dot**2" \
  --coordinates x --inputs y --time 1 --from 0 --to 1 -o out.csv
grep -q "the input 'y' is not a coordinate; the coordinates: x" stderr.txt && ok || bad "$(cat stderr.txt)"
expect_error 2 "a typed L without inputs" "--lagrangian needs --inputs: the coordinates the controls" optimize --lagrangian "0.5*x_dot**2" --coordinates x \
  --time 1 --from 0 --to 1 -o out.csv
expect_error 2 "a target beyond the joint limits" "urdf: a boundary position lies outside the position bounds" optimize --urdf "$data/pendulum.urdf" --time 3 \
  --from 0 --to 5 -o out.csv
grep -q "outside the position bounds" stderr.txt && ok || bad "$(cat stderr.txt)"
# Negative control: without the limits the same target is reached.
"$VARSYM" optimize --urdf "$data/pendulum.urdf" --no-limits --time 3 --steps 40 --from 0 --to 5 \
  --quiet -o free.csv 2> free.err && ok || bad "--no-limits: $(tail -1 free.err)"
sed 's/effort="100"/effort="0"/' "$data/pendulum.urdf" > passive.urdf
expect_error 2 "no actuated joint" "urdf: no joint of pendulum is actuated" optimize --urdf passive.urdf --time 3 --from 0 --to 1 -o out.csv
grep -q "is actuated (its URDF effort is 0 for every joint)" stderr.txt && ok || bad "$(cat stderr.txt)"
# A torque bound too small to swing the pendulum up in 3 s: IPOPT's infeasibility, exit 3, the
# last iterate written.
"$VARSYM" optimize --urdf "$data/pendulum.urdf" --time 3 --steps 40 --from 0 --to $pi \
  --max-control 0.2 --quiet -o weak.csv 2> weak.err
rc=$?
[ $rc -eq 3 ] && ok || bad "infeasible bound: exit $rc ($(tail -1 weak.err))"
[ "$(wc -l < weak.csv)" -eq 42 ] && ok || bad "infeasible bound: the last iterate was not kept"
finish
