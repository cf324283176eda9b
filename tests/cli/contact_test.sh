#!/usr/bin/env bash
# tests/cli/contact_test.sh VARSYM: robots touching the ground (--contact) through run, against
# closed forms: a dropped ball rests at its radius and never sinks, a sliding box stops at
# v0²/(2μg), a box on an incline below its friction angle does not creep; the contact columns,
# a killed and resumed run, and every refusal (exit 2, one line, nothing written).
data=$(realpath "$(dirname "$0")/../data/urdf")
source "$(dirname "$0")/lib.sh" "$@"
ball=$data/contact_ball.urdf
box=$data/contact_box.urdf
# column FILE NAME ROW: the value of a column in a data row ("last": the last one).
column() {
  awk -F, -v name="$2" -v row="$3" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
    c { v = $c; n = NR - 1; if (row != "last" && n == row) { print v; exit } }
    END { if (row == "last" && c) print v }' "$1"
}
# largest FILE NAME: the largest value of a column.
largest() {
  awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; m = -1e300; next }
    c && $c > m { m = $c } END { if (c && NR > 1) printf "%.6g", m }' "$1"
}

# --- a ball dropped from 0.3 m: rests at z = r = 0.1, never below -------------------------------
"$VARSYM" run --urdf "$ball" --base free --contact --q0 0,0,0.4,1,0,0,0 --scheme gauss \
  --degree 2 --time 1 --steps 1000 --every 10 -o drop.csv 2> drop.err && ok || bad "drop: $(cat drop.err)"
head -1 drop.csv | grep -q ',com_z,contacts,normal_impulse,friction_impulse,penetration,contact_work$' &&
  ok || bad "drop columns: $(head -1 drop.csv)"
z=$(column drop.csv q_base_z last)
between 0.099999999 "$z" 0.100000001 && ok || bad "drop: rests at z = $z, not 0.1"
p=$(largest drop.csv penetration)
lt "$p" 1e-12 && ok || bad "drop: penetration $p m"
c=$(column drop.csv contacts last)
[ "$c" = 1 ] && ok || bad "drop: $c contacts at rest, not 1"
# The impulse per step at rest is m g h = 9.81e-3 N s; the impact took m g 0.3 = 2.943 J, less
# the resting state's 1/2 m (g h/2)^2 = 1.2e-5 J (its end momentum, before the next impulse:
# docs/contact.md).
n=$(column drop.csv normal_impulse last)
between 0.009809999 "$n" 0.009810001 && ok || bad "drop: normal impulse $n N s at rest"
w=$(column drop.csv contact_work last)
between -2.942988 "$w" -2.942987 && ok || bad "drop: contact work $w J, not -m g 0.3"
b=$(largest drop.csv energy_balance)
lt "$b" 1e-12 && ok || bad "drop: energy balance $b J"

# --- a box sliding at 2 m/s with mu = 0.5 stops after v0^2/(2 mu g) = 0.407747 m ------------------
"$VARSYM" run --urdf "$box" --base free --contact --friction 0.5 --q0 0,0,0.1,1,0,0,0 \
  --v0 2,0,0,0,0,0,0 --scheme gauss --degree 2 --time 0.6 --steps 600 --every 600 -o slide.csv \
  2> slide.err && ok || bad "slide: $(cat slide.err)"
x=$(column slide.csv q_base_x last)
between 0.407745 "$x" 0.407749 && ok || bad "slide: stopped at $x m, not 0.407747"
# Negative control: friction 0.25 slides twice as far (within the run: 0.6 s at 2 m/s max).
"$VARSYM" run --urdf "$box" --base free --contact --friction 0.25 --q0 0,0,0.1,1,0,0,0 \
  --v0 2,0,0,0,0,0,0 --time 0.6 --steps 600 --every 600 -o slide2.csv 2> slide2.err &&
  ok || bad "slide 0.25: $(cat slide2.err)"
x2=$(column slide2.csv q_base_x last)
between 0.7 "$x2" 0.82 && ok || bad "slide 0.25: at $x2 m"

# --- on a planar base: the box dropped onto an incline below its friction angle sticks ----------
# The ground rises at 0.3 rad (tan 0.3 = 0.31 < mu = 1); the box (pitched to lie flat) starts
# 1 mm above it and, after landing, does not creep: base_x moves by less than 1e-6 m in 4 s.
"$VARSYM" run --urdf "$box" --base planar --contact --ground-slope 0.3 \
  --q0 -0.0298475,0.096489,-0.3 --time 5 --steps 5000 --every 1000 -o incline.csv 2> incline.err &&
  ok || bad "incline: $(cat incline.err)"
x1=$(column incline.csv q_base_x 2) # t = 1 s: landed
x5=$(column incline.csv q_base_x last)
d=$(awk -v a="$x1" -v b="$x5" 'BEGIN { d = a - b; if (d < 0) d = -d; printf "%.6g", d }')
lt "$d" 1e-6 && ok || bad "incline: crept $d m (from $x1 to $x5)"

# --- killed and resumed: byte-identical to a run that never stopped -----------------------------
# A box thrown spinning onto the ground, 24000 steps over 12 s (about 0.7 s at 30 us a step: it
# must outlast the first kill; 4000 steps ended within it), a checkpoint every 200; SIGKILL
# after 0.2 s (under the sanitizers after a new checkpoint), then resumed (and killed again)
# until it ends.
args=(run --urdf "$box" --base free --contact --friction 0.5 --q0 0,0,0.15,1,0,0,0
      --v0 1,0,0,0,0.3,0.2,0 --time 12 --steps 24000 --every 10 -o box.csv --checkpoint box.ckpt
      --checkpoint-every 200)
kill_and_resume box box.ckpt box.csv "${args[@]}"

# --- a real quadruped (Unitree A1, tests/data/urdf/a1.urdf): standing and dropped ---------------
# A free base and 12 joints under joint PD control (kp 80, kd 2) holding a crouch, its four
# sphere feet on the ground. It stands still: over the last 4 of 10 s the base moves less than
# 1e-6 m (measured 1.6e-7 m), the four feet carry M g h = 13.741 kg g h a step, and no foot sinks.
a1=$data/a1.urdf
legs=0,0.8,-1.5,0,0.8,-1.5,0,0.8,-1.5,0,0.8,-1.5
pd=(--kp 80,80,80,80,80,80,80,80,80,80,80,80 --kd 2,2,2,2,2,2,2,2,2,2,2,2 --target $legs)
"$VARSYM" run --urdf "$a1" --base free --contact --q0 0,0,0.3135,1,0,0,0,$legs "${pd[@]}" \
  --time 10 --steps 10000 --every 1000 -o stand.csv 2> stand.err && ok || bad "A1 standing: $(cat stand.err)"
for c in q_base_x q_base_y q_base_z; do
  a=$(column stand.csv $c 7) # t = 6 s
  b=$(column stand.csv $c last)
  d=$(awk -v a="$a" -v b="$b" 'BEGIN { d = a - b; if (d < 0) d = -d; printf "%.6g", d }')
  lt "$d" 1e-6 && ok || bad "A1 standing: $c moved $d m from t = 6 to 10 s"
done
c=$(column stand.csv contacts last)
[ "$c" = 4 ] && ok || bad "A1 standing on $c feet"
n=$(column stand.csv normal_impulse last)
between 0.1347991 "$n" 0.1347993 && ok || bad "A1 standing: normal impulse $n N s, not M g h"
# While the warm start's S is the kept one, the gaps agree with their linearisation to a tenth
# of the tolerance (1e-12 m), the interior point's to another tenth: a penetration of up to
# 2e-13 m. Steps on an exact S agree to the tolerance but converge quadratically, far inside it
# (measured 1.0e-13 m standing and 6.2e-14 m dropped; 9.99e-13 m with the whole tolerance on the
# kept S).
p=$(largest stand.csv penetration)
lt "$p" 2e-13 && ok || bad "A1 standing: penetration $p m"
# Dropped from 0.3 m higher: lands on its feet, never sinks, and settles to its stance height.
"$VARSYM" run --urdf "$a1" --base free --contact --q0 0,0,0.6135,1,0,0,0,$legs "${pd[@]}" \
  --time 2 --steps 2000 --every 20 -o a1drop.csv 2> a1drop.err && ok || bad "A1 dropped: $(cat a1drop.err)"
p=$(largest a1drop.csv penetration)
lt "$p" 2e-13 && ok || bad "A1 dropped: penetration $p m"
z=$(column a1drop.csv q_base_z last)
between 0.300 "$z" 0.310 && ok || bad "A1 dropped: base at $z m after 2 s"
c=$(column a1drop.csv contacts last)
[ "$c" = 4 ] && ok || bad "A1 dropped: on $c feet after 2 s"

# --- an ensemble of drops from four heights: each rests at its radius ----------------------------
rm -f ens.csv ens.csv.journal
"$VARSYM" ensemble --urdf "$ball" --base free --set contact=1 --set friction=0.3 \
  --q0 0 0 0.4 1 0 0 0 --grid q0_3=0.3:0.6:4 --time 0.5 --steps 500 --no-indicators -o ens.csv \
  2> ens.err && ok || bad "ensemble: $(cat ens.err)"
rested=$(awk -F, 'NR > 1 && $3 == "completed" && ($8 - 0.1 < 1e-9 && 0.1 - $8 < 1e-9) { n++ } END { print n + 0 }' ens.csv)
[ "$rested" = 4 ] && ok || bad "ensemble: $rested of 4 drops rest at z = 0.1: $(cut -d, -f1-8 ens.csv)"
expect_error 2 "indicators with contact" "--no-indicators" ensemble --urdf "$ball" --base free \
  --set contact=1 --q0 0 0 0.4 1 0 0 0 --grid q0_3=0.3:0.6:4 -o out.csv

# --- a step: the ball dropped onto a static box (x 1..3, 0.2 m high) rests on it at 0.2 + r ------
"$VARSYM" run --urdf "$ball" --base free --contact --boxes 2,0,0.1,2,2,0.2 \
  --q0 1.5,0,0.5,1,0,0,0 --time 1 --steps 1000 --every 1000 -o step.csv 2> step.err &&
  ok || bad "step: $(cat step.err)"
z=$(column step.csv q_base_z last)
between 0.299999999 "$z" 0.300000001 && ok || bad "step: the ball rests at z = $z, not 0.3"
expect_error 2 "boxes of five numbers" "six numbers a box" run --urdf "$ball" --base free \
  --contact --boxes 2,0,0.1,2,2 --q0 0,0,0.4,1,0,0,0 -o out.csv
expect_error 2 "a flat box" "positive finite sides" run --urdf "$ball" --base free --contact \
  --boxes 2,0,0.1,2,0,0.2 --q0 0,0,0.4,1,0,0,0 -o out.csv
expect_error 2 "a start inside a box" "inside the box 1" run --urdf "$ball" --base free \
  --contact --boxes 0,0,0.1,2,2,0.2 --q0 0,0,0.15,1,0,0,0 -o out.csv

# --- a fixed base: a pendulum (tests/data/urdf/pendulum.urdf, 0.5 m) with a ball of 0.05 m at its
# bob, released at 1.5 rad above a ground at z = -0.45: it swings down, hits the ground and
# rests on it where 0.5 cos(th) + 0.05 = 0.45, th = acos(0.8) = 0.6435011 rad.
awk '{ print } /<link name="bob">/ { print "    <collision><origin xyz=\"0 0 -0.5\"/><geometry><sphere radius=\"0.05\"/></geometry></collision>" }' \
  "$data/pendulum.urdf" > bob.urdf
"$VARSYM" run --urdf bob.urdf --contact --ground-height -0.45 --q0 1.5 --time 2 --steps 2000 \
  --every 100 -o bob.csv 2> bob.err && ok || bad "pendulum on the ground: $(cat bob.err)"
th=$(column bob.csv q_th last)
between 0.643501 "$th" 0.643502 && ok || bad "pendulum: rests at $th rad, not acos(0.8)"
expect_error 2 "a fixed base starting in the ground" "move the joints' start" run --urdf bob.urdf \
  --contact --ground-height -0.45 --q0 0 -o out.csv

# --- refusals --------------------------------------------------------------------------------------
expect_error 2 "negative friction" "friction" run --urdf "$box" --base free --contact \
  --friction -0.5 --q0 0,0,0.1,1,0,0,0 -o out.csv
expect_error 2 "friction without contact" "give contact too" run --urdf "$box" --base free \
  --friction 0.5 --q0 0,0,0.1,1,0,0,0 -o out.csv
expect_error 2 "a start below the ground" "inside the ground" run --urdf "$box" --base free \
  --contact --q0 0,0,0.05,1,0,0,0 -o out.csv
expect_error 2 "contact of a mesh" "link shoulder_link" run --urdf "$data/ur5_robot.urdf" --contact \
  -o out.csv
sed 's|<sphere radius="0.1"/>|<sphere radius="-0.1"/>|' "$ball" > bad_ball.urdf
expect_error 2 "a negative radius" "positive radius" run --urdf bad_ball.urdf --base free \
  --contact --q0 0,0,0.4,1,0,0,0 -o out.csv
# Without contact the collision shapes are not used: a bad one does not stop a run.
"$VARSYM" run --urdf bad_ball.urdf --base free --time 0.01 --steps 10 -o free.csv 2> free.err &&
  ok || bad "a bad <collision> refused without contact: $(cat free.err)"
expect_error 2 "infinite friction" "friction" run --urdf "$ball" --base free --contact \
  --friction inf --q0 0,0,0.4,1,0,0,0 -o out.csv
expect_error 2 "contact for the pendulum" "contact" run --model pendulum --contact -o out.csv
finish
