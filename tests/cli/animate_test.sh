#!/usr/bin/env bash
# tests/cli/animate_test.sh VARSYM: the 3-D animation pages of run --animate, optimize --animate
# and varsym animate: what the page holds (three.js inlined, the frames kept, the meshes found or
# warned about), their sizes, every refusal (exit 2, one line, nothing written, inputs intact), and
# the page in headless Chromium (animate_browser.py: the links' pixels against forward kinematics).
data=$(realpath "$(dirname "$0")/../data/urdf")
here=$(realpath "$(dirname "$0")")
source "$(dirname "$0")/lib.sh" "$@"
# frames FILE: the frames a page holds.
frames() { grep -o '"frames":[0-9]*' "$1" | cut -d: -f2; }
size() { stat -c %s "$1"; }

# A planar arm of three links (about +y): a red box, a blue STL mesh, a mesh that is missing.
inertial='<inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.001" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial>'
limit='<axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="20" velocity="10"/>'
cat > arm.urdf <<EOF
<robot name="viewer_arm">
  <material name="red"><color rgba="1 0 0 1"/></material>
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>$limit</joint>
  <link name="l1">$inertial
    <visual><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.08 0.08"/></geometry><material name="red"/></visual>
  </link>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.5 0 0"/>$limit</joint>
  <link name="l2">$inertial
    <visual><origin xyz="0.2 0 0"/><geometry><mesh filename="meshes/cube.stl" scale="0.4 0.08 0.08"/></geometry>
      <material name="blue"><color rgba="0 0 1 1"/></material></visual>
  </link>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.4 0 0"/>$limit</joint>
  <link name="l3">$inertial
    <visual><geometry><mesh filename="package://missing_pkg/meshes/tool.stl"/></geometry></visual>
  </link>
</robot>
EOF
mkdir -p meshes
{ # a unit cube centred at the origin, ASCII STL: two triangles per face
  echo "solid cube"
  for f in "1 0 0" "-1 0 0" "0 1 0" "0 -1 0" "0 0 1" "0 0 -1"; do
    set -- $f
    awk -v a="$1" -v b="$2" -v c="$3" 'BEGIN {
      # the face at n/2, its corners by two axes u, v orthogonal to n
      if (a != 0) { u = "0 1 0"; v = "0 0 1" } else if (b != 0) { u = "0 0 1"; v = "1 0 0" } else { u = "1 0 0"; v = "0 1 0" }
      split(u, U, " "); split(v, V, " "); n[1] = a; n[2] = b; n[3] = c
      # two triangles: (-,-) (+,-) (+,+) and (-,-) (+,+) (-,+) in (u, v)
      split("-1 1 1 -1 1 -1", S, " "); split("-1 -1 1 -1 1 1", R, " ")
      for (k = 0; k < 2; k++) {
        printf "facet normal %d %d %d\n outer loop\n", a, b, c
        for (j = 1; j <= 3; j++) {
          s = S[3 * k + j]; r = R[3 * k + j]
          printf "  vertex"
          for (i = 1; i <= 3; i++) printf " %g", n[i] / 2 + s * U[i] / 2 + r * V[i] / 2
          printf "\n"
        }
        printf " endloop\nendfacet\n"
      }
    }'
  done
  echo "endsolid cube"
} > meshes/cube.stl
cp arm.urdf arm.urdf.orig

# --- run --animate: every step kept, the meshes found or warned about --------------------------
"$VARSYM" run --urdf arm.urdf --q0 0.3,-0.5,0.2 --time 1 --steps 1000 -o arm.csv \
  --animate arm.html --animate-fps 0 2> arm.err && ok || bad "run --animate: $(cat arm.err)"
grep -q "^varsym: wrote arm.html (1001 frames" arm.err && ok || bad "report: $(cat arm.err)"
grep -q "warning: link l3: mesh 'package://missing_pkg/meshes/tool.stl' not found" arm.err &&
  ok || bad "missing-mesh warning: $(cat arm.err)"
[ "$(frames arm.html)" = 1001 ] && ok || bad "frames: $(frames arm.html), not 1001"
grep -q 'REVISION="111"' arm.html && grep -q 'data-varsym="STLLoader"' arm.html && ok ||
  bad "three.js r111 and its STL loader are not inlined"
grep -q 'data-varsym="ColladaLoader"\|data-varsym="OBJLoader"' arm.html && bad "loaders inlined that no mesh needs" || ok
grep -q '"k":"mesh"' arm.html && grep -q '"k":"capsule"' arm.html && ok ||
  bad "the page lacks the mesh or the fallback capsules"
[ "$(grep -c '<script src' arm.html)" = 0 ] && [ "$(grep -c '<script data-varsym=' arm.html)" = 3 ] && ok ||
  bad "the page's scripts are not three, OrbitControls and STLLoader inlined"
between 800000 "$(size arm.html)" 2000000 && ok || bad "page size $(size arm.html) B"
cmp -s arm.urdf arm.urdf.orig && ok || bad "the URDF changed"

# --- decimation: 60 frames per second of motion by default; a 10^5-row run stays small ----------
"$VARSYM" run --urdf arm.urdf --q0 0.3,-0.5,0.2 --time 1 --steps 1000 --every 0 -o /dev/null \
  --animate d.html 2> d.err && ok || bad "default fps: $(cat d.err)"
n=$(frames d.html)
between 58 "$n" 63 && ok || bad "default fps kept $n frames of 1 s"
start=$(date +%s.%N)
"$VARSYM" run --urdf arm.urdf --q0 0.3,-0.5,0.2 --time 20 --steps 100000 --every 0 -o /dev/null \
  --animate long.html -q 2> long.err && ok || bad "10^5 steps: $(cat long.err)"
echo "10^5 steps with --animate: $(frames long.html) frames, $(size long.html) B, $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }') s"
between 1150 "$(frames long.html)" 1250 && ok || bad "20 s at 60 fps: $(frames long.html) frames"
lt "$(size long.html)" 3000000 && ok || bad "20 s page: $(size long.html) B"

# --- contact: the ground drawn, and the contact points of each frame -----------------------------
"$VARSYM" run --urdf "$data/contact_ball.urdf" --base free --contact --q0 0,0,0.4,1,0,0,0 \
  --time 1 --steps 1000 -o ball.csv --animate ball.html 2> ball.err && ok || bad "ball: $(cat ball.err)"
grep -q '"obstacles":\[{"k":"plane","n":\[-\?0,0,1\],"d":0}\]' ball.html && ok ||
  bad "the ground is not in the ball's page"
touches=$(grep -o '"touches":"[^"]*"' ball.html | cut -d'"' -f4 | base64 -d | od -An -tu4 | tr -s ' \n' ' ')
[ "$(echo $touches | awk '{ print $1 }')" = 0 ] && [ "$(echo $touches | awk '{ print $NF }')" = 1 ] &&
  ok || bad "the ball's contact points per frame: $touches (in the air first, then one)"
# Its force arrows: none in the air; at rest on the ground at t = 1 s, one arrow from the ground
# holding its weight, m g = 1 kg x 9.81 m/s^2 (the impulse of a step over h; float32 in the page).
counts=$(grep -o '"arrowCounts":"[^"]*"' ball.html | cut -d'"' -f4 | base64 -d | od -An -tu4 | tr -s ' \n' ' ')
last=$(grep -o '"arrows":"[^"]*"' ball.html | cut -d'"' -f4 | base64 -d | od -An -tf4 -w24 -v | tail -1)
[ "$(echo $counts | awk '{ print $1 }')" = 0 ] && [ "$(echo $counts | awk '{ print $NF }')" = 1 ] &&
  echo "$last" | awk '{ exit !($3 < 1e-6 && $3 > -1e-6 && $4 * $4 + $5 * $5 < 1e-6 && ($6 - 9.81)^2 < 1e-6) }' &&
  ok || bad "the ball's force arrows: counts $counts, the last (point, force) $last (want 0 0 0 0 0 9.81)"
grep -q 'id="note">blue arrows: the contact forces' ball.html && ok || bad "the page does not state the arrows' scale"

# --- the built-in models' figures ------------------------------------------------------------------
"$VARSYM" run --model spherical-pendulum --time 1 --steps 1000 -o pend.csv --animate pend.html \
  --animate-fps 0 2> pend.err && ok || bad "spherical-pendulum --animate: $(cat pend.err)"
[ "$(frames pend.html)" = 1001 ] && grep -q '"names":\["x","y","z"\]' pend.html && ok ||
  bad "the pendulum's page: $(frames pend.html) frames, names $(grep -o '"names":[^]]*' pend.html)"
for m in heavy-top top pendulum-3d rigid-body arm double-pendulum; do
  "$VARSYM" run --model "$m" --time 2 --steps 200 -o "fig_$m.csv" --animate "fig_$m.html" -q \
    2> "fig_$m.err" && between 118 "$(frames "fig_$m.html")" 122 && ok ||
    bad "$m --animate: $(cat "fig_$m.err")"
done
grep -q 'id="note">drawn with its centre of mass 1 m' fig_heavy-top.html && ok ||
  bad "the heavy top's page does not say its drawn scale"
# Stopped by the energy watch (its relative error reaches 2e-8): the page ends where the run did.
"$VARSYM" run --model heavy-top --time 20 --steps 200 --max-energy-error 1e-9 -o stop.csv \
  --animate stop.html 2> stop.err
[ $? = 4 ] && grep -q "ends where the run stopped" stop.err && lt "$(frames stop.html)" 200 && ok ||
  bad "a stopped heavy-top run's page: $(cat stop.err)"

# --- varsym animate: the same page from the CSV ---------------------------------------------------
"$VARSYM" animate --urdf arm.urdf --input arm.csv --output again.html --fps 0 2> again.err && ok ||
  bad "animate: $(cat again.err)"
[ "$(frames again.html)" = 1001 ] && ok || bad "animate kept $(frames again.html) frames"
cmp -s <(grep -o '"poses":"[^"]*"' arm.html) <(grep -o '"poses":"[^"]*"' again.html) && ok ||
  bad "the page from the CSV differs from the run's (17-digit rows, same float poses)"
"$VARSYM" animate --urdf "$data/pendulum.urdf" --input arm.csv --output x.html 2> x.err
[ $? = 2 ] && grep -q "has no column q_" x.err && [ ! -e x.html ] && ok ||
  bad "another robot's CSV: $(cat x.err)"

# --- optimize --animate --------------------------------------------------------------------------
if "$VARSYM" optimize --help > /dev/null 2>&1; then
  "$VARSYM" optimize --urdf arm.urdf --time 1 --steps 20 --from 0,0,0 --to 0.5,0.3,0 --quiet \
    -o opt.csv --animate opt.html 2> opt.err && ok || bad "optimize --animate: $(cat opt.err)"
  between 55 "$(frames opt.html)" 65 && ok || bad "optimize: $(frames opt.html) frames of 1 s"
  "$VARSYM" optimize --model arm --time 1 --steps 20 --from 0,0,0 --to 1,0.5,0.2 --quiet \
    -o optarm.csv --animate optarm.html 2> optarm.err && grep -q '"title":"arm: optimal motion"' optarm.html &&
    ok || bad "optimize --model arm --animate: $(cat optarm.err)"
else
  skip "varsym optimize is not built (no IPOPT)"
fi

# --- refusals: exit 2, one line, nothing written, inputs intact ----------------------------------
expect_error 2 "--animate on a model without a figure" "no 3-D figure" run --animate out.html
expect_error 2 "--mesh-path on a built-in model" "has none" run --model heavy-top \
  --animate out.html --mesh-path meshes
expect_error 2 "--animate over the URDF" "--animate" run --urdf arm.urdf --animate arm.urdf -o out.csv
cmp -s arm.urdf arm.urdf.orig && ok || bad "--animate arm.urdf damaged the URDF"
expect_error 2 "--animate with --checkpoint" "resumed run" run --urdf arm.urdf --animate a.html \
  -o out.csv --checkpoint ck
expect_error 2 "--animate to a directory" "file name" run --urdf arm.urdf --animate meshes -o out.csv
expect_error 2 "--animate-fps alone" "--animate" run --urdf arm.urdf --animate-fps 30 -o out.csv
expect_error 2 "animate over its input" "--input" animate --urdf arm.urdf --input arm.csv --output arm.csv
expect_error 2 "animate over the URDF" "--urdf" animate --urdf arm.urdf --input arm.csv --output arm.urdf
cmp -s arm.urdf arm.urdf.orig && ok || bad "animate damaged the URDF"
[ -e a.html ] && bad "a refused run wrote a.html" || ok

# --- a picture of the page (headless Chromium) ----------------------------------------------------
if command -v chromium > /dev/null; then
  "$VARSYM" animate --urdf arm.urdf -i arm.csv -o s.html --snapshot s.png --snapshot-times 0,0.5,1 \
    2> s.err && ok || bad "--snapshot: $(cat s.err)"
  [ "$(head -c 24 s.png | tail -c 8 | od -An -tu1 | tr -s ' ')" = " 0 0 4 176 0 0 3 32" ] && ok ||
    bad "--snapshot: not a 1200x800 PNG"
  [ -e s.png.tmp.png ] && bad "--snapshot left its temporary file" || ok
else
  skip "--snapshot: no Chromium (apt-get install chromium)"
fi
expect_error 2 "--snapshot-times outside the motion" "outside" animate --urdf arm.urdf -i arm.csv \
  -o out.csv --snapshot x.png --snapshot-times 5

# --- the page in a real browser --------------------------------------------------------------------
/usr/bin/python3 "$here/animate_browser.py" "$PWD"
case $? in
0) ok ;;
77) skip "the browser checks (Chromium or matplotlib missing)" ;;
*) bad "the browser checks (above)" ;;
esac
finish
