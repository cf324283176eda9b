#!/usr/bin/env bash
# tests/cli/checkpoint_test.sh VARSYM: long runs that are never lost (issue 6). A run killed with
# SIGKILL at random moments and resumed each time ends byte-identical to a run that never
# stopped; damaged or foreign checkpoints are refused; a failed step leaves a checkpoint of the
# last good state and an exit-3 message with a safer step; the stability limits are right.
source "$(dirname "$0")/lib.sh" "$@"

# --- SIGKILL at >= 5 random moments, resume each time, compare with cmp --------------------------
# Simpson steps of the pendulum, as many as take about 3 s in this build (2e7 in Release, about
# 2e6 under the sanitizers; timed from a 1e6-step run), a checkpoint every 1 % of the run. The
# kills come after random pauses of 4 % to 15 % of the uninterrupted run's duration, so each
# attempt gets past a checkpoint and about ten kills happen whatever the build's speed (at least
# seven if its speed holds).
t0=$(date +%s%N)
"$VARSYM" run --time 50 --steps 1000000 --every 0 -o calibrate.csv || bad "timing run failed"
steps=$(awk -v ns="$(( $(date +%s%N) - t0 ))" 'BEGIN { n = int(3e9 / ns * 10) * 1e5;
  if (n < 1e6) n = 1e6; if (n > 2e7) n = 2e7; printf "%d", n }')
args=(run --time 1000 --steps "$steps" --every 1000 -o run.csv --checkpoint run.ckpt
      --checkpoint-every $((steps / 100)))
mkdir straight killed
t0=$(date +%s%N)
(cd straight && "$VARSYM" "${args[@]}") || bad "uninterrupted run failed"
duration=$(( $(date +%s%N) - t0 )) # ns
cd killed || exit 1
kills=0 rc=1 sleeps=""
for attempt in $(seq 1 400); do
  if [ -e run.ckpt ]; then "$VARSYM" run --resume run.ckpt 2>> stderr.txt &
  else rm -f run.csv.part; "$VARSYM" "${args[@]}" 2>> stderr.txt & fi
  pid=$!
  pause=$(awk -v d="$duration" -v r="$RANDOM" 'BEGIN { printf "%.3f", d * 1e-9 * (0.04 + 0.11 * r / 32767) }')
  sleeps="$sleeps $pause"
  sleep "$pause"
  kill -9 "$pid" 2> /dev/null
  { wait "$pid"; } 2> /dev/null # without bash's "Killed" notice
  rc=$?
  [ "$rc" -eq 137 ] && kills=$((kills + 1)) && continue
  break
done
[ "$rc" -eq 0 ] && ok || bad "resumed run ended with $rc: $(cat stderr.txt)"
[ "$kills" -ge 5 ] && ok || bad "only $kills kills (sleeps:$sleeps)"
cmp run.csv ../straight/run.csv && ok || bad "CSV after $kills kills differs (sleeps:$sleeps)"
# The final state, with the compensated-summation carries, bit for bit (hexadecimal floats);
# only the absolute output path and hence the checksum differ between the two directories.
state() { grep -v '^output \|^crc32 ' "$1"; }
diff <(state run.ckpt) <(state ../straight/run.ckpt) > /dev/null && ok ||
  bad "final checkpoint differs after $kills kills"
[ ! -e run.csv.part ] && ok || bad "run.csv.part left after completion"
echo "checkpoint_test: $steps steps, $kills kills at random moments (sleeps:$sleeps), resumed each time"
# Resuming a completed run changes nothing and says so.
cp run.csv before.csv
"$VARSYM" run --resume run.ckpt 2> stderr.txt && grep -q 'is complete' stderr.txt && cmp -s run.csv before.csv &&
  ok || bad "resume of a complete run: $(cat stderr.txt)"
cd ..

# --- a run started from a config file resumes without it --------------------------------------
# 5e5 steps (about 0.2 s in Release, 6 s under the sanitizers). The run is killed as soon as its
# first checkpoint (step 20000 of 500000) exists, whatever the build's speed; a fixed pause
# could come before any checkpoint under the sanitizers and after the end in Release.
printf 'model = "kepler"\nperiods = 100\nsteps-per-period = 5000\nevery = 100\n' > k.toml
"$VARSYM" run --config k.toml -o k.csv > /dev/null 2>&1 && mv k.csv k_straight.csv
"$VARSYM" run --config k.toml -o k.csv --checkpoint k.ckpt --checkpoint-every 20000 & pid=$!
for i in $(seq 1 6000); do [ -e k.ckpt ] && break; sleep 0.01; done
kill -9 $pid 2> /dev/null; { wait $pid; } 2> /dev/null
rm k.toml
[ -e k.ckpt ] && ok || bad "kepler run wrote no checkpoint in 60 s"
"$VARSYM" run --resume k.ckpt 2> stderr.txt && cmp -s k.csv k_straight.csv && ok ||
  bad "kepler resume without its config file: $(cat stderr.txt)"

# --- a run whose steps depend on the previous one resumes bit for bit ---------------------------
# killed_and_resumed NAME WHAT ARGS...: runs `ARGS` straight to NAME_straight.csv, and again with
# a checkpoint every 10 000 steps, killed as soon as its first checkpoint exists; not vacuous (a
# finished run would leave NAME.csv, not NAME.csv.part); then resumed, its rows and its final
# checkpoint's history equal to the straight run's.
killed_and_resumed() {
  local name=$1 what=$2; shift 2
  "$VARSYM" "$@" -o "${name}_straight.csv" --checkpoint "${name}_straight.ckpt" || bad "$what run failed"
  "$VARSYM" "$@" -o "$name.csv" --checkpoint "$name.ckpt" --checkpoint-every 10000 & pid=$!
  for i in $(seq 1 6000); do [ -e "$name.ckpt" ] && break; sleep 0.01; done
  kill -9 $pid 2> /dev/null; { wait $pid; } 2> /dev/null
  [ -e "$name.csv.part" ] && [ ! -e "$name.csv" ] && ok || bad "the $what run ended before it was killed"
  "$VARSYM" run --resume "$name.ckpt" 2> stderr.txt && cmp -s "$name.csv" "${name}_straight.csv" &&
    diff <(grep '^history' "$name.ckpt") <(grep '^history' "${name}_straight.ckpt") > /dev/null &&
    ok || bad "resume of a run with $what: $(cat stderr.txt)"
}
# gauss-4 on Kepler starting each step from the previous step's polynomial and keeping its
# Jacobian across steps: the checkpoint carries that history. 2e5 steps (about 0.2 s in
# Release). The final checkpoint holds the history (a 1 first: a previous step to continue).
killed_and_resumed h "--predictor previous" run --model kepler --scheme gauss --degree 4 \
  --iteration simplified --predictor previous --periods 400 --steps-per-period 500 --every 100
[ "$(grep -c '^history 1p+0 ' h.ckpt)" = 1 ] && ok ||
  bad "the checkpoint's history line: $(grep '^history' h.ckpt | cut -c1-80)"
# The same with the forces start (the previous step's gradients and contraction rate).
killed_and_resumed fs "--predictor forces" run --model kepler --scheme gauss --degree 4 \
  --predictor forces --periods 2000 --steps-per-period 500 --every 500

# --- refused checkpoints and options: exit 2, one line ------------------------------------------
"$VARSYM" run --steps-per-period 100 --periods 20 -o c.csv --checkpoint c.ckpt --checkpoint-every 100 2> /dev/null
cp c.ckpt good.ckpt
sed 's/^step \(.*\)/step 1\1/' good.ckpt > c.ckpt   # one more digit in the step
expect_error 2 "damaged checkpoint" "checkpoint 'c.ckpt' is damaged (CRC-32 checksum mismatch)" run --resume c.ckpt
grep -q 'damaged (CRC-32' stderr.txt && ok || bad "damaged message: $(cat stderr.txt)"
head -c 200 good.ckpt > c.ckpt
expect_error 2 "truncated checkpoint" "checkpoint 'c.ckpt' is damaged" run --resume c.ckpt
sed 's/^version .*/version 0.0.1/' good.ckpt > c.ckpt
expect_error 2 "checkpoint of another version" "was written by varsym 0.0.1, this is varsym" run --resume c.ckpt
grep -q 'written by varsym 0.0.1' stderr.txt && ok || bad "version message: $(cat stderr.txt)"
echo 'step,t,q,p' > c.ckpt
expect_error 2 "not a checkpoint" "'c.ckpt' is not a varsym checkpoint" run --resume c.ckpt
expect_error 2 "missing checkpoint" "cannot read checkpoint 'nowhere.ckpt': No such file or" run --resume nowhere.ckpt
cp good.ckpt c.ckpt
expect_error 2 "resume with other options" "--resume FILE takes no other option: the run continues with" run --resume c.ckpt --steps-per-period 10
expect_error 2 "checkpoint exists" "checkpoint 'c.ckpt' exists: continue its run with 'varsym" run -o out.csv --checkpoint c.ckpt
grep -q 'resume' stderr.txt && ok || bad "exists message: $(cat stderr.txt)"
expect_error 2 "checkpoint without output" "--checkpoint needs --output naming a regular file: a" run --checkpoint new.ckpt
expect_error 2 "checkpoint-every without checkpoint" "--checkpoint-every requires --checkpoint" run -o out.csv --checkpoint-every 10
expect_error 2 "zero checkpoint-every" "--checkpoint-every: must be >= 1, got '0'" run -o out.csv --checkpoint new.ckpt --checkpoint-every 0
expect_error 2 "NaN checkpoint-seconds" "--checkpoint-seconds: 'nan' is not finite" run -o out.csv --checkpoint new.ckpt --checkpoint-seconds nan
expect_error 2 "checkpoint is the output" "--output 'same.csv' and --checkpoint 'same.csv' are the" run -o same.csv --checkpoint same.csv
expect_error 1 "unwritable checkpoint" "cannot write checkpoint '/nonexistent/dir/c.ckpt'" run -o out.csv --checkpoint /nonexistent/dir/c.ckpt
# A run whose rows are gone, or shorter than its checkpoint says, cannot resume (the checkpoint
# alone cannot rebuild them).
"$VARSYM" run --steps-per-period 100 --periods 20 -o gone.csv --checkpoint gone.ckpt 2> /dev/null && rm gone.csv
expect_error 2 "resume with its rows gone" "the rows of the interrupted run, is missing" run --resume gone.ckpt
grep -q 'gone.csv.part.*missing' stderr.txt && ok || bad "rows-gone message: $(cat stderr.txt)"
"$VARSYM" run --steps-per-period 100 --periods 20 -o cut.csv --checkpoint cut.ckpt 2> /dev/null &&
  head -c 100 cut.csv > cut.csv.part && rm cut.csv
expect_error 2 "resume with rows cut" "has 100 bytes, fewer than the" run --resume cut.ckpt
grep -q 'fewer than the' stderr.txt && ok || bad "rows-cut message: $(cat stderr.txt)"

# --- a failed step: exit 3, safer step, checkpoint of the last good state ------------------------
# Simpson on the double pendulum with h = 0.5 s fails in step 15 (h*omega ~ 2.5 near its limit).
"$VARSYM" run --model double-pendulum --time 10 --steps 20 --max-energy-error 0 -o f.csv \
  > /dev/null 2> stderr.txt
[ $? -eq 3 ] && [ "$(wc -l < stderr.txt)" -eq 1 ] && ok || bad "failed step: $(cat stderr.txt)"
grep -q 'did not converge in step [0-9]* (t = .*residual .*omega_max = .*try h <= ' stderr.txt && ok ||
  bad "failed-step message: $(cat stderr.txt)"
failed=$(sed 's/.*in step \([0-9]*\) .*/\1/' stderr.txt)
[ -e f.csv.part ] && [ ! -e f.csv ] && [ -e f.csv.ckpt ] && ok || bad "failed run's files: $(ls f.csv*)"
# The checkpoint holds the last good step, whose q is the last row's (hexadecimal vs 17 digits).
[ "$(sed -n 's/^step //p' f.csv.ckpt)" -eq $((failed - 1)) ] && ok || bad "failure checkpoint step"
last_q1=$(tail -1 f.csv.part | cut -d, -f3)
ck_q1=$(sed -n 's/^q \([^ ]*\).*/\1/p' f.csv.ckpt)
case $ck_q1 in -*) ck_q1="-0x${ck_q1#-}" ;; *) ck_q1="0x$ck_q1" ;; esac
[ "$(printf '%.17g' "$ck_q1")" = "$(printf '%.17g' "$last_q1")" ] && ok ||
  bad "failure checkpoint q_1 $ck_q1 vs last row $last_q1"

# --- linear stability limits (varsym stability) ------------------------------------------------
# Closed forms: Lobatto 1 (Stoermer-Verlet) is stable for h*omega < 2; Simpson's step map of
# q'' = -q has trace 2 - a/3 - (2a/3 - a^2/18)/(1 + a/24), a = (h omega)^2 (derived from eq.
# simpson-hamilton), which passes -2 at a = 8 and returns at a = 12, then passes +2 at a = 24:
# unstable on (2 sqrt 2, 2 sqrt 3) and beyond 2 sqrt 6. Gauss members (A-stable collocation)
# and Newmark (midpoint rule) never are.
"$VARSYM" stability --format csv > stab.csv 2> stderr.txt || bad "stability: $(cat stderr.txt)"
limit() { awk -F, -v s="$1" '$1 == s { print $3 }' stab.csv; }
intervals() { awk -F, -v s="$1" '$1 == s { print $4 }' stab.csv; }
near_limit() { rel "$1" "$2" 1e-7; } # the limits are printed to 8 digits
near_limit "$(limit lobatto-1)" 2 && ok || bad "lobatto-1 limit $(limit lobatto-1)"
near_limit "$(limit simpson)" "$(awk 'BEGIN { printf "%.17g", 2 * sqrt(2) }')" && [ "$(limit lobatto-2)" = "$(limit simpson)" ] &&
  ok || bad "simpson limit $(limit simpson)"
read -r a b c d <<< "$(intervals simpson | tr '();' '   ')"
near_limit "$b" "$(awk 'BEGIN { printf "%.17g", 2 * sqrt(3) }')" && near_limit "$c" "$(awk 'BEGIN { printf "%.17g", 2 * sqrt(6) }')" &&
  [ "$d" = inf ] && ok || bad "simpson intervals $(intervals simpson)"
for s in newmark gauss-1 gauss-2 gauss-3 gauss-4 gauss-5 gauss-6 gauss-7 gauss-8; do
  [ "$(limit $s)" = none ] || bad "$s limit $(limit $s)"
done
# Higher Lobatto members: a finite limit that grows with the order (every second member).
for s in 1 2 3 4 5 6; do
  lt "$(limit lobatto-$s)" "$(limit lobatto-$((s + 2)))" ||
    bad "lobatto-$((s + 2)) limit not above lobatto-$s's"
done
ok

finish
