#!/usr/bin/env bash
# tests/cli/inputs_test.sh VARSYM: the files a command reads are never damaged and are the ones
# its run was started with. An input (URDF, --config, --ipopt-options, --members, a checkpoint)
# is never an output, directly or through a link; a resumed run or a rerun ensemble refuses a
# robot that changed or moved; inputs that are not regular files are refused at once; ensemble
# keys that alias or are ambiguous are refused; options of another kind of model are refused.
data=$(realpath "$(dirname "$0")/../data/urdf")
source "$(dirname "$0")/lib.sh" "$@"
cp "$data/pendulum.urdf" r.urdf
cp r.urdf r.orig
ln -s r.urdf link.urdf
# unharmed NAME: r.urdf still holds the robot (cmp against the copy taken above).
unharmed() { cmp -s r.urdf r.orig && ok || bad "$1: r.urdf was changed"; }

# --- an input is never a target ----------------------------------------------------------------
expect_error 2 "run -o the URDF" "--output 'r.urdf' and --urdf 'r.urdf' are the same file" \
  run --urdf r.urdf --time 0.1 --steps 10 -o r.urdf
unharmed "run -o r.urdf"
expect_error 2 "run -o a link to the URDF" "are the same file" \
  run --urdf r.urdf --time 0.1 --steps 10 -o link.urdf
unharmed "run -o link.urdf"
expect_error 2 "run --checkpoint the URDF" "are the same file" \
  run --urdf r.urdf --time 0.1 --steps 10 -o out.csv --checkpoint r.urdf
unharmed "run --checkpoint r.urdf"
printf 'time = 0.1\nsteps = 10\n' > c.toml
cp c.toml c.orig
expect_error 2 "run -o its config" "are the same file" run --config c.toml -o c.toml
cmp -s c.toml c.orig && ok || bad "run -o c.toml changed the config"
expect_error 2 "ensemble -o the URDF" "are the same file" \
  ensemble --urdf r.urdf --grid q0_1=0:1:2 --time 0.1 --steps 10 -o link.urdf
unharmed "ensemble -o link.urdf"
expect_error 2 "section -o the URDF" "are the same file" \
  section --urdf r.urdf --grid q0_1=0.5:1:2 --plane q1=0 --time 1 --steps 100 -o r.urdf
unharmed "section -o r.urdf"
printf 'q0_1\n0.5\n' > members.csv
expect_error 2 "ensemble -o its --members file" "are the same file" \
  ensemble --model pendulum --members members.csv -o members.csv
for out in "-o r.urdf" "--controls link.urdf"; do
  # shellcheck disable=SC2086 # $out is two words on purpose
  expect_error 2 "optimize $out" "are the same file" \
    optimize --urdf r.urdf --time 1 --steps 10 --from 0 --to 0.5 $out
  unharmed "optimize $out"
done
printf 'print_level 0\noutput_file r.urdf\n' > ipopt.opt
expect_error 2 "IPOPT's output_file on the URDF" "are the same file" \
  optimize --urdf r.urdf --time 1 --steps 10 --from 0 --to 0.5 --ipopt-options ipopt.opt -o out.csv
unharmed "IPOPT output_file r.urdf"
expect_error 2 "optimize -o its IPOPT options file" "are the same file" \
  optimize --urdf r.urdf --time 1 --steps 10 --from 0 --to 0.5 --ipopt-options ipopt.opt -o ipopt.opt
grep -q 'output_file r.urdf' ipopt.opt && ok || bad "the IPOPT options file was changed"
# Negative control: the same commands with other outputs run, and leave the URDF as it was.
"$VARSYM" run --urdf link.urdf --time 0.1 --steps 10 -o fine.csv 2> err.txt &&
  [ "$(wc -l < fine.csv)" -eq 12 ] && ok || bad "run -o fine.csv: $(cat err.txt)"
unharmed "run -o fine.csv"

# --- optimize --reach reads its robot once: removing the URDF during the solve changes nothing ---
cp "$data/iiwa14_no_collision.urdf" arm.urdf
"$VARSYM" optimize --urdf arm.urdf --time 2 --steps 200 --from 0,0,0,0,0,0,0 \
  --reach iiwa_link_ee --reach-position 0.1,0,1.2 -o reach.csv 2> reach.err &
pid=$!
for i in $(seq 1 1000); do grep -q "iteration" reach.err 2> /dev/null && break; sleep 0.01; done
rm arm.urdf
wait "$pid"
rc=$?
[ "$rc" -eq 0 ] && grep -q "iiwa_link_ee ends [0-9.e-]* m from its target" reach.err && ok ||
  bad "reach with its URDF removed mid-solve: exit $rc: $(tail -1 reach.err)"
grep -q "iteration" reach.err && ok || bad "the URDF was not removed during the solve"

# --- inputs that are not regular files: refused at once, with the reason -------------------------
mkfifo fifo.urdf
mkdir dir.urdf
for input in /dev/zero fifo.urdf; do
  start=$(date +%s%N)
  expect_error 2 "--urdf $input" "not a regular file" run --urdf "$input" --time 0.1 --steps 10
  ms=$(( ($(date +%s%N) - start) / 1000000 ))
  lt "$ms" 2000 && ok || bad "--urdf $input took $ms ms to refuse"
done
expect_error 2 "--urdf a directory" "it is a directory" run --urdf dir.urdf --time 0.1 --steps 10
expect_error 2 "--ipopt-options a directory" "it is a directory" \
  optimize --urdf r.urdf --time 1 --steps 10 --from 0 --to 0.5 --ipopt-options dir.urdf -o out.csv

# --- a resumed run knows its robot ---------------------------------------------------------------
# A run of 2e6 pendulum steps (seconds), killed once its first checkpoint is there.
mkdir -p a b
cp r.urdf a/robot.urdf
start_and_kill() { # DIR: starts the run in DIR with a relative --urdf, kills it at its checkpoint
  (cd "$1" && exec "$VARSYM" run --urdf robot.urdf --q0 1 --time 2000 --steps 2000000 \
    --every 1000 -o run.csv --checkpoint run.ckpt --checkpoint-every 20000 2> /dev/null) &
  local pid=$! i
  for i in $(seq 1 500); do [ -e "$1/run.ckpt" ] && break; sleep 0.02; done
  kill -9 "$pid" 2> /dev/null
  { wait "$pid"; } 2> /dev/null
  [ -e "$1/run.ckpt" ] && ok || bad "no checkpoint in $1 to resume"
}
start_and_kill a
grep -q "^arg $(realpath a)/robot.urdf$" a/run.ckpt && ok || bad "the checkpoint keeps a relative --urdf"
grep -q '^input crc32:[0-9a-f]\{8\},bytes:[0-9]* ' a/run.ckpt && ok || bad "no input digest in the checkpoint"
# The URDF edited (a heavier bob): the resume is refused and the rows kept.
sed 's/mass value="1.0"/mass value="2.0"/' r.urdf > a/robot.urdf
expect_error 2 "resume after the URDF changed" "changed since the run started" run --resume a/run.ckpt
[ -s a/run.csv.part ] && ok || bad "the refused resume lost the rows"
# Restored, it resumes, from another directory too: the checkpoint names the absolute path,
# and a file of that name in the working directory is not read.
cp r.urdf a/robot.urdf
sed 's/mass value="1.0"/mass value="3.0"/' r.urdf > b/robot.urdf
(cd b && "$VARSYM" run --resume ../a/run.ckpt 2> ../err.txt) && ok || bad "resume from b/: $(cat err.txt)"
[ -e a/run.csv ] && [ ! -e b/run.csv ] && ok || bad "the resumed run wrote elsewhere"
# Its energy is the 1 kg pendulum's throughout (E = -4.905 cos(1) = -2.6502 J, to 1e-6 J with
# Simpson's order-4 error at h = 1 ms): the 3 kg file in b/ was not read.
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "energy") c = i; next }
  { d = $c + 2.65018; if (d < 0) d = -d; if (d > m) m = d } END { exit !(c && NR > 100 && m < 1e-4) }' \
  a/run.csv && ok || bad "the resumed run's energy is not the 1 kg pendulum's"
# The URDF moved away: refused, naming the file.
start_and_kill b
mv b/robot.urdf b/moved.urdf
expect_error 2 "resume after the URDF moved" "robot.urdf" run --resume b/run.ckpt

# --- an ensemble rerun after the robot changed does not mix two robots ---------------------------
cp r.urdf e.urdf
ens=(ensemble --urdf e.urdf --grid q0_1=0:1:400 --time 20 --steps 20000 --threads 1 -o ens.csv)
"$VARSYM" "${ens[@]}" 2> /dev/null &
pid=$!
for i in $(seq 1 500); do [ -s ens.csv.journal ] && [ "$(wc -l < ens.csv.journal)" -gt 3 ] && break; sleep 0.02; done
kill -9 "$pid" 2> /dev/null
{ wait "$pid"; } 2> /dev/null
[ -s ens.csv.journal ] && ok || bad "no journal to continue"
sed 's/mass value="1.0"/mass value="2.0"/' r.urdf > e.urdf
expect_error 2 "ensemble rerun after the URDF changed" "belongs to another ensemble" "${ens[@]}"

# --- ensemble keys: one value, one name ----------------------------------------------------------
expect_error 2 "two keys of one coordinate" "set the same value" \
  ensemble --urdf r.urdf --grid q0_1=0:1:2 --grid q0_th=0:1:2 --time 0.1 --steps 10 -o out.csv
sed 's/joint name="th"/joint name="2"/; s/<robot name="pendulum">/<robot name="two">/' r.urdf |
  awk '/<\/robot>/ { print "  <link name=\"tip\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>"
       print "  <joint name=\"1\" type=\"revolute\"><parent link=\"bob\"/><child link=\"tip\"/><axis xyz=\"0 1 0\"/><limit lower=\"-4\" upper=\"4\" effort=\"10\" velocity=\"10\"/></joint>" }
       { print }' > two.urdf
expect_error 2 "a joint named 1 that is coordinate 2" "is ambiguous" \
  ensemble --urdf two.urdf --grid q0_1=0:1:2 --time 0.1 --steps 10 -o out.csv
# Negative control: q0_2 is the joint named 2, which is coordinate 1: ambiguous too; the
# unambiguous spellings run.
"$VARSYM" ensemble --urdf r.urdf --grid q0_th=0:1:2 --time 0.1 --steps 10 -o fine.csv 2> err.txt &&
  ok || bad "ensemble q0_th: $(cat err.txt)"

# --- options of another kind of model are refused ------------------------------------------------
expect_error 2 "optimize --urdf --constraints" "--constraints: --coordinates, --parameters, --inputs and --constraints are a typed Lagrangian's options" \
  optimize --urdf r.urdf --time 1 --steps 10 --from 0 --to 0.5 --constraints 'th' -o out.csv
expect_error 2 "optimize --urdf --inputs" "--inputs: --coordinates, --parameters, --inputs and --constraints are a typed Lagrangian's options" \
  optimize --urdf r.urdf --time 1 --steps 10 --from 0 --to 0.5 --inputs th -o out.csv
expect_error 2 "converge --model pendulum --urdf" "--urdf is for --model urdf" \
  converge --model pendulum --urdf r.urdf -o out.csv

finish
