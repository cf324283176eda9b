#!/usr/bin/env bash
# docs/figures/animation.sh VARSYM [MESH_DIR]: draws docs/figures/animation_ur5.png, a picture of
# the animation page of the UR5's minimum-effort move (varsym optimize --animate; then varsym
# animate --snapshot, headless Chromium): the arm at the end, faint at 0, 0.5, 1 and 1.5 s.
# MESH_DIR holds example-robot-data (its robots/ur_description/meshes, BSD 3-Clause; e.g. an
# export of github.com/Gepetto/example-robot-data at 39aa9437): without it the links are drawn as
# capsules.
set -eu
varsym=$(realpath "${1:?usage: $0 PATH_TO_VARSYM [MESH_DIR]}")
meshes=()
[ $# -ge 2 ] && meshes=(--mesh-path "$(realpath "$2")")
urdf=$(cd "$(dirname "$0")/../../tests/data/urdf" && pwd)/ur5_robot.urdf
out=$(cd "$(dirname "$0")" && pwd)/animation_ur5.png
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
"$varsym" optimize --urdf "$urdf" --time 2 --steps 40 --from 0,-1.5,1.5,0,0,0 \
  --to 1.5,-0.5,0.5,-1,0.8,0 --quiet -o ur5.csv
"$varsym" animate --urdf "$urdf" --input ur5.csv --output ur5.html "${meshes[@]}" \
  --snapshot ur5.png --snapshot-times 0,0.5,1,1.5,2
mv ur5.png "$out"
echo "wrote $out"
