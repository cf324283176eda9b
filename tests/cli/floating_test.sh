#!/usr/bin/env bash
# tests/cli/floating_test.sh VARSYM: robots with a floating base (--base free or planar) through
# run, converge and ensemble. References: Noether's theorem (the total momenta of a robot in free
# flight are conserved to round-off; its columns momentum_*, angular_momentum_*), the unit
# quaternion's constraint, the orders 4 of Simpson and gauss-2 measured by converge, and every
# refusal (exit 2, one line, nothing written).
data=$(realpath "$(dirname "$0")/../data/urdf")
source "$(dirname "$0")/lib.sh" "$@"
ur5=$data/ur5_robot.urdf
# max_dev FILE COLUMN_NAME: the largest |value − first value| of that column; nothing (which lt
# refuses) without the column or a data row.
max_dev() {
  awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
    c && NR == 2 { v0 = $c } c { v = $c - v0; if (v < 0) v = -v; if (v > m) m = v }
    END { if (NR > 1 && c) printf "%.6g", m }' "$1"
}
# A rigid body of one link (principal inertias 1, 2, 3 kg m², centre off the link's origin).
cat > body.urdf <<'URDF'
<?xml version="1.0"?>
<robot name="tumbling_body">
  <link name="body">
    <inertial>
      <origin xyz="0.1 -0.2 0.05" rpy="0.3 0.2 0.1"/>
      <mass value="2.0"/>
      <inertia ixx="1.0" ixy="0" ixz="0" iyy="2.0" iyz="0" izz="3.0"/>
    </inertial>
  </link>
</robot>
URDF

# --- a tumbling body: both momenta to round-off, the quaternion on its sphere -------------------
# From rest in translation, spinning near its unstable middle axis (rates 1, 0.1, 2 rad/s in
# v0 = 1/2 q * (0, w)), 20 s at h = 0.01: |L| ≈ 6.4 N m s; round-off over 2000 steps, 1e-12.
"$VARSYM" run --urdf body.urdf --base free --gravity 0 --v0 0,0,0,0,0.5,0.05,1.0 \
  --scheme gauss --degree 2 --time 20 --steps 2000 --every 10 -o body.csv 2> body.err &&
  ok || bad "body run: $(cat body.err)"
head -1 body.csv | grep -q '^step,t,q_base_x,q_base_y,q_base_z,q_base_qw,q_base_qx,q_base_qy,q_base_qz,p_base_x,.*,energy,work,energy_balance,limit_violations,quaternion_residual,base_vx,.*,angular_momentum_z,com_x,com_y,com_z$' &&
  ok || bad "body columns: $(head -1 body.csv)"
for c in angular_momentum_x angular_momentum_y angular_momentum_z momentum_x momentum_y \
  momentum_z quaternion_residual; do
  d=$(max_dev body.csv $c)
  lt "$d" 1e-12 && ok || bad "body: $c moved by $d"
done
# Energy: bounded, the order-4 error at h|w| ≈ 0.02 (measured 1e-9 J of 7.2 J).
e=$(max_dev body.csv energy)
lt "$e" 1e-7 && ok || bad "body: energy error $e J"
# Negative control: with gravity the vertical momentum falls (by M g t = 392 N s).
"$VARSYM" run --urdf body.urdf --base free --v0 0,0,0,0,0.5,0.05,1.0 --time 20 --steps 2000 \
  --every 100 -o fall.csv 2> fall.err && ok || bad "falling body: $(cat fall.err)"
d=$(max_dev fall.csv momentum_z)
between 392.3 "$d" 392.5 && ok || bad "falling body: momentum_z changed by $d N s, not M g t"

# --- a floating UR5 driven by joint torques: momenta stay zero, the base turns -----------------
"$VARSYM" run --urdf "$ur5" --base free --gravity 0 --torque 1,-2,1,0.5,0.3,0.2 --time 1 \
  --steps 1000 --every 10 -o arm.csv 2> arm.err && ok || bad "floating UR5: $(cat arm.err)"
for c in momentum_x momentum_y momentum_z angular_momentum_x angular_momentum_y \
  angular_momentum_z; do
  d=$(max_dev arm.csv $c)
  lt "$d" 1e-11 && ok || bad "floating UR5: $c moved by $d"
done
d=$(max_dev arm.csv q_base_qw)
lt 0.1 "$d" && ok || bad "floating UR5: the base did not turn ($d)"

# --- a planar base: x, z and the pitch; the horizontal momentum conserved ----------------------
"$VARSYM" run --urdf "$ur5" --base planar --torque 1,-2,1,0.5,0.3,0.2 --time 0.5 --steps 500 \
  --every 10 -o planar.csv 2> planar.err && ok || bad "planar UR5: $(cat planar.err)"
head -1 planar.csv | grep -q '^step,t,q_base_x,q_base_z,q_base_ry,q_shoulder_pan_joint,' &&
  ok || bad "planar columns: $(head -1 planar.csv)"
d=$(max_dev planar.csv momentum_x)
lt "$d" 1e-11 && ok || bad "planar UR5: momentum_x moved by $d"

# --- converge measures the orders through the quaternion's constraint ---------------------------
"$VARSYM" converge --urdf body.urdf --base free --set gravity=0 --set p0_5=0.5 --set p0_7=1.5 \
  --time 5 --scheme gauss --degree 2 -o conv.csv > conv.txt 2> conv.err &&
  ok || bad "converge: $(cat conv.err)"
awk '$1 == "fitted" { exit !($2 > 3.9 && $2 < 4.1) }' conv.txt && ok ||
  bad "converge: fitted order: $(cat conv.txt)"

# --- an ensemble of spins ------------------------------------------------------------------------
"$VARSYM" ensemble --urdf body.urdf --base free --grid p0_5=0.1:1:4 --set gravity=0 --time 1 \
  --steps 100 -o ens.csv > ens.txt 2> ens.err && [ "$(grep -c ',completed,' ens.csv)" = 4 ] &&
  ok || bad "ensemble: $(cat ens.err ens.txt)"

# --- a run killed and resumed ends byte-identical to one that never stopped ---------------------
# 60000 steps of the tumbling body (about 2 s at 30 µs a step), a checkpoint every 1000;
# SIGKILL after 0.2 s (under the sanitizers after a new checkpoint), then resumed (and killed
# again) until it ends.
args=(run --urdf "$PWD/body.urdf" --base free --gravity 0 --v0 0,0,0,0,0.5,0.05,1.0
      --time 600 --steps 60000 --every 100 -o tumble.csv --checkpoint tumble.ckpt
      --checkpoint-every 1000)
kill_and_resume tumble tumble.ckpt tumble.csv "${args[@]}"

# --- refusals -----------------------------------------------------------------------------------
expect_error 2 "--base for the pendulum" "--base is a parameter of --model urdf" \
  run --model pendulum --base free -o out.csv
expect_error 2 "--base sideways" "--base" run --urdf body.urdf --base sideways -o out.csv
expect_error 2 "a single link, bolted down" "nothing moves" run --urdf body.urdf -o out.csv
printf '<robot name="ghost">\n  <link name="body"/>\n</robot>\n' > massless.urdf
expect_error 2 "a massless free base" "carries no mass" \
  run --urdf massless.urdf --base free -o out.csv
expect_error 2 "a quaternion off the sphere" "unit length" \
  run --urdf body.urdf --base free --q0 0,0,0,1,0.1,0,0 -o out.csv
expect_error 2 "a quaternion rate off the sphere" "keep its length" \
  run --urdf body.urdf --base free --v0 0,0,0,0.5,0,0,0 -o out.csv
expect_error 2 "kp for the base too" "joint" \
  run --urdf "$ur5" --base free --kp 1,1,1,1,1,1,1,1,1,1,1,1,1 -o out.csv
expect_error 2 "converge --base for the pendulum" "--base is for --model urdf" \
  converge --model kepler --base free -o out.csv
finish
