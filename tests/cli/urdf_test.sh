#!/usr/bin/env bash
# tests/cli/urdf_test.sh VARSYM: robots from URDF files (`--urdf FILE`, the model urdf) through
# run, converge and ensemble. References: the energy (conserved without forces, balanced by the
# forces' work with them), the orders 2s of gauss-s and 4 of Simpson measured by converge against
# gauss-8 at twice the steps, a PD controller's target, and every refusal (exit 2, one line).
data=$(realpath "$(dirname "$0")/../data/urdf")
source "$(dirname "$0")/lib.sh" "$@"
ur5=$data/ur5_robot.urdf
iiwa=$data/iiwa14_no_collision.urdf
# max_abs FILE COLUMN_NAME: the largest |value| of that column; nothing (which lt refuses)
# without the column or a data row.
max_abs() {
  awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
    c { v = $c < 0 ? -$c : $c; if (v > m) m = v } END { if (NR > 1 && c) printf "%.3g", m }' "$1"
}

# --- a passive UR5 conserves its energy (gauss-2, h = 1 ms, 2 s of free fall and swing) --------
"$VARSYM" run --urdf "$ur5" --q0 0,-1,1,0,0.5,0 --scheme gauss --degree 2 --time 2 --steps 2000 \
  --every 100 -o ur5.csv 2> ur5.err && ok || bad "UR5 run: $(cat ur5.err)"
head -1 ur5.csv | grep -q '^step,t,q_shoulder_pan_joint,q_shoulder_lift_joint,.*,p_wrist_3_joint,energy,work,energy_balance,limit_violations$' &&
  ok || bad "UR5 columns: $(head -1 ur5.csv)"
# E ≈ 51 J; the order-4 error at h ω ≈ 0.02 is far below 1e-7 of it (measured 3e-9 J).
e=$(max_abs ur5.csv energy_balance)
lt "$e" 1e-6 && ok || bad "UR5 energy error $e J"

# --- the articulated iteration (O(n) solves with M) takes Newton's steps: the same rows ----------
"$VARSYM" run --urdf "$ur5" --q0 0,-1,1,0,0.5,0 --scheme gauss --degree 2 --time 2 --steps 2000 \
  --every 100 --iteration articulated -o ur5_art.csv 2> ur5_art.err && ok ||
  bad "UR5 articulated: $(cat ur5_art.err)"
# Both solve each step's equations to round-off; their rows differ by what rounding adds up to
# over 2000 steps (measured 5.7e-14). (That the iteration converges by itself, not by handing its
# steps to Newton, is tests/multibody/test_articulated_iteration.cpp's to check.)
gap=$(paste -d, ur5.csv ur5_art.csv | awk -F, 'NR > 1 { n = NF / 2; for (i = 1; i <= n; ++i) {
  d = $i - $(i + n); d = d < 0 ? -d : d; if (d > m) m = d } } END { if (NR > 1) printf "%.3g", m }')
lt "$gap" 1e-10 && ok || bad "UR5 articulated against newton: $gap"

# --- the URDF's joint damping: energy falls by the damping's work --------------------------------
"$VARSYM" run --urdf "$iiwa" --q0 0.3,1,0,-1,0,0.5,0 --scheme gauss --degree 2 --time 2 \
  --steps 2000 --every 100 -o iiwa.csv 2> iiwa.err && ok || bad "iiwa run: $(cat iiwa.err)"
e=$(max_abs iiwa.csv energy_balance)
lt "$e" 1e-6 && ok || bad "iiwa energy balance $e J"
w=$(tail -1 iiwa.csv | awk -F, '{ print $(NF - 2) }')
lt "$w" -1 && ok || bad "iiwa: damping took no energy ($w J)"
# Negative control: without the damping nothing is taken.
"$VARSYM" run --urdf "$iiwa" --no-damping --q0 0.3,1,0,-1,0,0.5,0 --time 2 --steps 2000 \
  --every 2000 -o free.csv 2> free.err && [ "$(tail -1 free.csv | awk -F, '{ print $(NF - 2) }')" = 0 ] &&
  ok || bad "--no-damping: $(tail -1 free.csv)"

# --- PD control with gravity compensation reaches its target -----------------------------------
"$VARSYM" run --urdf "$iiwa" --kp 400,400,300,300,100,50,20 --kd 40,40,30,30,10,5,2 \
  --target 0.5,0.5,0,-1,0,0.5,0 --move-time 1 --time 3 --steps 3000 --every 3000 -o pd.csv \
  2> pd.err && ok || bad "PD run: $(cat pd.err)"
tail -1 pd.csv | awk -F, '{ t[1] = 0.5; t[2] = 0.5; t[3] = 0; t[4] = -1; t[5] = 0; t[6] = 0.5; t[7] = 0
  for (i = 1; i <= 7; ++i) { d = $(i + 2) - t[i]; if (d < 0) d = -d; if (d > m) m = d }
  exit !(m < 1e-3) }' && ok || bad "PD did not reach the target: $(tail -1 pd.csv | cut -d, -f1-9)"
# Held where it starts, upright at q = 0: the motion is round-off of the cancelled gravity
# torques, and each step stops where its residual is round-off (docs/design.md). Before that
# stop, Newton's updates cycled there and step 9773 failed.
"$VARSYM" run --urdf "$iiwa" --kp 400,400,300,300,100,50,20 --kd 40,40,30,30,10,5,2 --scheme gauss \
  --degree 2 --time 10 --steps 10000 --every 10000 -o upright.csv 2> upright.err && ok ||
  bad "held upright: $(cat upright.err)"
q=$(tail -1 upright.csv | awk -F, '{ m = 0; for (i = 3; i <= 9; ++i) { d = $i < 0 ? -$i : $i
  if (d > m) m = d }; print m }')
lt "$q" 1e-12 && ok || bad "held upright: moved to |q| = $q"

# --- joint torques typed in t and the joints' names: their work balances the energy ----------
"$VARSYM" run --urdf "$ur5" --q0 0,-1,1,0,0.5,0 --torques "5*sin(3*t),0,-2*elbow_joint_dot,0,0,0" \
  --scheme gauss --degree 2 --time 2 --steps 2000 --every 100 -o typed.csv 2> typed.err && ok ||
  bad "typed torques: $(cat typed.err)"
e=$(max_abs typed.csv energy_balance)
lt "$e" 1e-6 && ok || bad "typed torques: energy balance $e J"
w=$(max_abs typed.csv work)
lt 0.1 "$w" && ok || bad "typed torques did no work ($w J)"
# Constant torques (--torque) are the typed constants: the same rows.
"$VARSYM" run --urdf "$ur5" --q0 0,-1,1,0,0.5,0 --torque 1,2,0,0,0,0 --time 0.5 --steps 500 \
  --every 500 -o const.csv 2> /dev/null &&
  "$VARSYM" run --urdf "$ur5" --q0 0,-1,1,0,0.5,0 --torques 1,2,0,0,0,0 --time 0.5 --steps 500 \
    --every 500 -o const2.csv 2> /dev/null && cmp -s const.csv const2.csv && ok ||
  bad "--torque and --torques of the same constants differ"

# --- orders: gauss-s is of order 2s, Simpson 4, on the 3-D UR5 --------------------------------
order() { # order ARGS...: the fitted order of the state error over the last pair of step counts
  "$VARSYM" converge --urdf "$ur5" --set q0_2=-1 --set q0_3=1 --set q0_5=0.5 --time 1 \
    --steps 20,40,80,160 "$@" 2>&1 | awk '$1 == 160 { gsub(/[()]/, "", $5); print $5 }'
}
for s in 1 2 3 4; do
  k=$(order --scheme gauss --degree "$s")
  near "$k" $((2 * s)) 0.35 && ok ||
    bad "gauss-$s on the UR5: order $k, expected $((2 * s))"
done
k=$(order --scheme simpson)
between 3.7 "$k" 4.3 && ok || bad "Simpson on the UR5: order $k"

# --- an ensemble over a joint's start (--urdf implies --model urdf) -----------------------------
"$VARSYM" ensemble --urdf "$ur5" --grid q0_2=-1.5:-0.5:3 --time 0.5 --steps 500 -o ens.csv \
  2> ens.err && grep -q '3 completed' ens.err && [ "$(wc -l < ens.csv)" -eq 4 ] && ok ||
  bad "ensemble: $(cat ens.err)"

# Members by joint name: q0_shoulder_lift_joint is q0_2 (the same rows).
"$VARSYM" ensemble --urdf "$ur5" --grid q0_shoulder_lift_joint=-1.5:-0.5:3 --time 0.5 \
  --steps 500 -o named.csv 2> named.err && ok || bad "ensemble by joint name: $(cat named.err)"
[ "$(cut -d, -f3- named.csv | tail -3)" = "$(cut -d, -f3- ens.csv | tail -3)" ] && ok ||
  bad "q0_shoulder_lift_joint and q0_2 differ"
# A section of the swinging arm (dense output of the general engine).
"$VARSYM" section --urdf "$ur5" --grid q0_2=-1.5:-0.5:2 --plane q1=0 --time 5 --steps 5000 \
  -o sec.csv 2> sec.err && grep -q '2 orbits' sec.err && [ "$(wc -l < sec.csv)" -gt 2 ] && ok ||
  bad "section: $(cat sec.err)"

# --- refusals: exit 2, one line, nothing written ------------------------------------------------
expect_error 2 "missing URDF" "--urdf: cannot read URDF file 'no_such.urdf': No such file" run --urdf no_such.urdf -o out.csv
# The real Panda runs, its second finger mimicking the first (not a column); a mimic of an
# unknown joint is refused with the line.
"$VARSYM" run --urdf "$data/panda.urdf" --time 0.01 --steps 10 -o panda.csv 2> panda.err &&
  grep -q "q_panda_finger_joint1" panda.csv && ! grep -q "finger_joint2" panda.csv && ok ||
  bad "mimic Panda: $(cat panda.err)"
sed 's/mimic joint="panda_finger_joint1"/mimic joint="nothing"/' "$data/panda.urdf" > mimic.urdf
expect_error 2 "mimic of an unknown joint" "<mimic>: joint panda_finger_joint2 mimics nothing" run --urdf mimic.urdf -o out.csv
grep -q "mimic.urdf:348: <mimic>: joint panda_finger_joint2 mimics nothing" stderr.txt && ok ||
  bad "$(cat stderr.txt)"
printf '<robot name="r"><link name="a"/>\n' > broken.urdf
expect_error 2 "malformed XML" "--urdf: broken.urdf:1: malformed XML: XML_ERROR_PARSING" run --urdf broken.urdf -o out.csv
sed 's/type="revolute"/type="floating"/' "$ur5" > floating.urdf
expect_error 2 "floating joint" "floating joints are not supported" run --urdf floating.urdf -o out.csv
sed 's/izz="0.00666"/izz="0.1"/' "$ur5" > triangle.urdf
expect_error 2 "triangle inequality" "break the triangle inequality" run --urdf triangle.urdf -o out.csv
grep -q "link shoulder_link: principal moments .* break the triangle inequality" stderr.txt && ok ||
  bad "$(cat stderr.txt)"
expect_error 2 "articulated, not a robot" "the articulated iteration is for robots (URDF models)" run --model pendulum --iteration articulated -o out.csv
expect_error 2 "articulated, general engine" "the articulated iteration is for robots (URDF models" run --model double-pendulum --iteration articulated -o out.csv
expect_error 2 "articulated, free base" "a robot with a free base is a constrained system, solved by Newton" run --urdf "$data/a1.urdf" --base free --iteration articulated -o out.csv
expect_error 2 "no --urdf" "--model urdf needs --urdf FILE, the robot's URDF description" run --model urdf -o out.csv
expect_error 2 "--urdf with another model" "--urdf is for --model urdf, not 'kepler'" converge --model kepler --urdf "$ur5"
expect_error 2 "kp count" "urdf: kp needs 6 values (one per joint), got 2" run --urdf "$ur5" --kp 1,2 -o out.csv
expect_error 2 "target without kp" "urdf: target without kp: the PD controller needs its gains" run --urdf "$ur5" --target 0,0,0,0,0,0 -o out.csv
expect_error 2 "q0 count" "urdf: q0 needs 6 values" run --urdf "$ur5" --q0 1,2 -o out.csv
expect_error 2 "torque of an unknown name" "--torques: unknown name 'hand' at column 1 of \"hand\"" run --urdf "$ur5" --torques "hand,0,0,0,0,0" -o out.csv
expect_error 2 "torques count" "--torques: the joint torques need 6 expressions" run --urdf "$ur5" --torques "1,2" -o out.csv
expect_error 2 "torques and torque" "urdf: give constant torques or typed ones, not both" run --urdf "$ur5" --torques 1,0,0,0,0,0 --torque 1,0,0,0,0,0 \
  -o out.csv
expect_error 2 "--torques for another model" "--torques is a parameter of --model urdf, not of --model kepler" run --model kepler --torques 1 -o out.csv
expect_error 2 "unknown joint key" "'q0_hand' is not a key of urdf; its keys: q0_1 p0_1 q0_2" ensemble --urdf "$ur5" --grid q0_hand=1:2:2 -o out.csv

finish
