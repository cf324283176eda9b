#!/usr/bin/env bash
# tests/cli/files_test.sh VARSYM: nothing lost, nothing silently wrong (docs/cli.md, "Files,
# locking, signals"). Special files are written through, never replaced; the files of one command
# never collide; concurrent runs and resumes are refused; reads are bounded; numbers are read in
# decimal, correctly rounded; reading the wrong kind of file, a watchdog stop and a signal each
# give their exit code and one line; output that cannot be written is a failure.
source "$(dirname "$0")/lib.sh" "$@"

# wait_stepping PID PART: waits (up to 20 s) until PART holds a row after row 0, or the run PID
# has ended (status 1). A run writes its header and row 0 before it watches for signals: a signal
# before then ends it without a checkpoint.
wait_stepping() {
  for _ in $(seq 2000); do
    [ "$({ wc -l < "$2"; } 2> /dev/null || echo 0)" -gt 2 ] && return 0
    kill -0 "$1" 2> /dev/null || return 1
    sleep 0.01
  done
  return 1
}

# --- special files: written through, still what they were ------------------------------------
mkfifo fifo
cat fifo > from_fifo.txt &
reader=$!
"$VARSYM" run -o fifo 2> stderr.txt && ok || bad "run -o FIFO: $(cat stderr.txt)"
wait "$reader"
[ -p fifo ] && ok || bad "the FIFO was replaced"
[ "$(wc -l < from_fifo.txt)" -eq 52 ] && ok || bad "the FIFO's reader got $(wc -l < from_fifo.txt) lines"
cat fifo > table_fifo.txt &
reader=$!
"$VARSYM" paper table1 --format csv -o fifo 2> stderr.txt && ok || bad "paper -o FIFO"
wait "$reader"
grep -q '^simpson,' table_fifo.txt && [ -p fifo ] && ok || bad "table1 through the FIFO"
# A picture to a FIFO: drawn into a private temporary file, then written through.
mkfifo pic.svg
cat pic.svg > got.svg &
reader=$!
"$VARSYM" paper figure1 -o pic.svg 2> stderr.txt && ok || bad "figure to a FIFO: $(cat stderr.txt)"
wait "$reader"
[ -p pic.svg ] && grep -q '</svg>' got.svg && [ -s pic.csv ] && [ -s pic.gp ] && ok ||
  bad "the FIFO's reader did not get the SVG"
[ -z "$(ls -A | grep '^\.varsym-')" ] && ok || bad "temporary files left: $(ls -A)"
# A character device made here (root only: skipped, and said, elsewhere).
if mknod null c 1 3 2> /dev/null; then
  "$VARSYM" run --model kepler -o null 2> stderr.txt && [ -c null ] && [ ! -e null.part ] && ok ||
    bad "run -o a character device: $(cat stderr.txt); $(ls -l null*)"
  "$VARSYM" converge --steps 10,20 -o null 2> /dev/null && [ -c null ] && ok || bad "converge -o device"
else
  skip "not root: the mknod character-device case"
fi
"$VARSYM" run -o /dev/stdout > through_stdout.txt 2> stderr.txt && ok || bad "run -o /dev/stdout"
[ "$(wc -l < through_stdout.txt)" -eq 52 ] && [ -L /dev/stdout ] && ok || bad "/dev/stdout output"
# A symbolic link to a regular file stays a link; its target gets the rows.
echo old > target.csv && ln -s target.csv link.csv
"$VARSYM" run -o link.csv 2> /dev/null && [ -L link.csv ] && [ "$(wc -l < target.csv)" -eq 52 ] &&
  ok || bad "link to a regular file"
# A dangling link creates its target, atomically too: SIGTERM leaves no partial file under the
# final name, only TARGET.part and the checkpoint; the resumed run ends with the uninterrupted
# run's bytes, and the link is still a link. The run (about a second in Release) is stopped as
# soon as it steps (wait_stepping).
ln -s far.csv dangling.csv
"$VARSYM" run --model pendulum --time 20 --steps 2000000 --every 10 -o dangling.csv --quiet \
  2> /dev/null &
pid=$!
wait_stepping $pid far.csv.part
kill -TERM $pid && wait $pid
rc=$?
[ $rc -eq 143 ] && [ ! -e far.csv ] && [ -s far.csv.part ] && [ -s dangling.csv.ckpt ] && ok ||
  bad "SIGTERM through a dangling link: exit $rc, $(ls far.csv* dangling.csv* | tr '\n' ' ')"
"$VARSYM" run --resume dangling.csv.ckpt 2> /dev/null && ok || bad "resume through the link"
"$VARSYM" run --model pendulum --time 20 --steps 2000000 --every 10 -o direct.csv --quiet \
  2> /dev/null
cmp -s far.csv direct.csv && [ -L dangling.csv ] && [ ! -e far.csv.part ] && ok ||
  bad "the resumed run through a dangling link differs from the uninterrupted one"
rm -f far.csv direct.csv

# --- collisions: every pair of roles, refused before anything is written ----------------------
printf 'model = "kepler"\n' > c.toml
cp c.toml c.toml.orig
collide() { # NAME ARGS...: exit 2 naming two roles; c.toml unchanged; no file left
  local name=$1
  shift
  rm -rf o.csv o.csv.part ck ck.tmp o.csv.ckpt
  "$VARSYM" "$@" > /dev/null 2> stderr.txt
  local rc=$?
  if [ $rc -eq 2 ] && grep -q 'are the same file' stderr.txt && cmp -s c.toml c.toml.orig &&
     [ ! -e o.csv ] && [ ! -e o.csv.part ] && [ ! -e ck ]; then ok; else
    bad "collision $name: exit $rc: $(cat stderr.txt)"; fi
}
collide "output = config" run --config c.toml -o c.toml
cp c.toml cfg.part
"$VARSYM" run --config cfg.part -o cfg > /dev/null 2> stderr.txt
[ $? -eq 2 ] && grep -q 'same file' stderr.txt && cmp -s cfg.part c.toml && [ ! -e cfg ] && ok ||
  bad "partial = config: $(cat stderr.txt)"
collide "checkpoint = output" run -o o.csv --checkpoint o.csv
collide "checkpoint = partial" run -o o.csv --checkpoint o.csv.part
collide "checkpoint = config" run --config c.toml -o o.csv --checkpoint c.toml
collide "checkpoint tmp = output" run -o ck.tmp --checkpoint ck
collide "checkpoint tmp = partial" run -o ck.tmp.x --checkpoint ck.tmp.x.part 2> /dev/null
cp c.toml o.csv.ckpt && cp c.toml o.csv.ckpt.orig
"$VARSYM" run --config o.csv.ckpt -o o.csv > /dev/null 2> stderr.txt
[ $? -eq 2 ] && grep -q 'same file' stderr.txt && cmp -s o.csv.ckpt o.csv.ckpt.orig && ok ||
  bad "failure checkpoint = config: $(cat stderr.txt)"
rm -f o.csv.ckpt o.csv.ckpt.orig
cp c.toml ck.tmp
"$VARSYM" run --config ck.tmp -o o.csv --checkpoint ck > /dev/null 2> stderr.txt
[ $? -eq 2 ] && grep -q 'same file' stderr.txt && [ -e ck.tmp ] && ok || bad "ck.tmp = config"
rm -f ck.tmp
collide "two pictures" paper figure1 -o f.svg -o f.svg
collide "table = plot data" converge --steps 10,20 -o conv.csv --plot conv.png
collide "bench table = plot data" bench --problems pendulum --schemes simpson --steps 10,20 \
  --periods 1 --repetitions 1 -o wp-pendulum.csv --plot wp.svg
# Negative control: distinct names pass.
rm -f o.csv* ck*
"$VARSYM" run --config c.toml -o o.csv --checkpoint ck 2> stderr.txt && [ -e o.csv ] && [ -e ck ] &&
  ok || bad "distinct files refused: $(cat stderr.txt)"
# Files the run did not create are never removed: an unrelated CK.tmp, a stale FILE.part.
rm -f o.csv* ck*
echo mine > ck.tmp
expect_error 2 "existing CK.tmp" "'ck.tmp' exists; varsym writes checkpoint 'ck' through that" run -o o.csv --checkpoint ck
[ "$(cat ck.tmp)" = mine ] && ok || bad "CK.tmp was changed"
echo mine > o.csv.part
expect_error 2 "existing FILE.part" "cannot write 'o.csv': 'o.csv.part' exists" run -o o.csv
[ "$(cat o.csv.part)" = mine ] && grep -q "o.csv.part' exists" stderr.txt && ok || bad "FILE.part kept"
rm -f o.csv* ck*

# --- locking: a second run on the same output, a second resume of one checkpoint --------------
long=(run --time 100 --steps 400000000 --every 1000000 -o busy.csv --checkpoint busy.ck
      --checkpoint-every 1000000)
"$VARSYM" "${long[@]}" 2> first.txt &
first=$!
for _ in $(seq 100); do [ -e busy.ck ] && break; sleep 0.1; done
expect_error 2 "second run on the same output" "another varsym run is writing 'busy.csv'" run -o busy.csv
grep -q 'is locked' stderr.txt && ok || bad "lock message: $(cat stderr.txt)"
kill -TERM "$first"
wait "$first"
rc=$?
[ $rc -eq 143 ] && grep -q "stopped by SIGTERM after step .*resume busy.ck" first.txt && ok ||
  bad "SIGTERM: exit $rc: $(cat first.txt)"
"$VARSYM" run --resume busy.ck 2> first.txt &
first=$!
sleep 0.5
expect_error 2 "second resume" "busy.csv.part' is locked by another varsym run" run --resume busy.ck
grep -q 'locked by another varsym run' stderr.txt && ok || bad "resume lock: $(cat stderr.txt)"
kill -INT "$first"
wait "$first"
[ $? -eq 130 ] && ok || bad "SIGINT of a resumed run: $(cat first.txt)"
# Another run's rows in place of FILE.part: the resume sees it by the CRC-32 and refuses.
cp busy.csv.part busy.saved
sed -i '2s/^0,0,/0,0,9/' busy.csv.part
cmp -s busy.csv.part busy.saved && bad "the rows were not changed"
timeout 20 "$VARSYM" run --resume busy.ck > /dev/null 2> stderr.txt
rc=$?
[ $rc -eq 2 ] && grep -q 'CRC-32' stderr.txt && ok || bad "resume over changed rows: $rc $(cat stderr.txt)"
mv busy.saved busy.csv.part
rm -f busy.*

# --- SIGINT and SIGTERM: checkpoint, resume, byte-identical to a run that never stopped -------
args=(run --time 100 --steps 3000000 --every 1000 -o sig.csv)
mkdir straight && (cd straight && "$VARSYM" "${args[@]}") || bad "uninterrupted run"
for sig in INT TERM; do
  rm -f sig.csv*
  "$VARSYM" "${args[@]}" 2> sig.txt &
  pid=$!
  wait_stepping "$pid" sig.csv.part
  kill -$sig "$pid"
  wait "$pid"
  rc=$?
  if [ $rc -eq 0 ]; then echo "files_test: the run ended before SIG$sig; not a check"; continue; fi
  code=$([ $sig = INT ] && echo 130 || echo 143)
  [ $rc -eq "$code" ] && [ -e sig.csv.ckpt ] && grep -q "resume sig.csv.ckpt" sig.txt && ok ||
    bad "SIG$sig: exit $rc, $(cat sig.txt)"
  "$VARSYM" run --resume sig.csv.ckpt 2> stderr.txt && cmp -s sig.csv straight/sig.csv && ok ||
    bad "SIG$sig resumed run differs: $(cat stderr.txt)"
done
"$VARSYM" run --time 100 --steps 300000000 --every 0 > /dev/null 2> sig.txt &
pid=$!
sleep 0.3
kill -INT "$pid"
wait "$pid"
[ $? -eq 130 ] && grep -q 'stopped by SIGINT' sig.txt && ok || bad "SIGINT to stdout: $(cat sig.txt)"

# A second signal ends the run at once: here the run is blocked writing to a FIFO nobody
# reads, so the first SIGINT (which waits for the step to finish) cannot take effect.
rm -f stuck
mkfifo stuck
(exec 3< stuck; sleep 20) &
holder=$!
"$VARSYM" run --time 100 --steps 1000000 -o stuck 2> sig.txt &
pid=$!
sleep 1
kill -INT "$pid"
sleep 1.2 # a second signal within a second of the first counts as the same request
kill -0 "$pid" 2> /dev/null && ok || bad "one SIGINT ended a run blocked in a write"
kill -INT "$pid"
for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
kill -0 "$pid" 2> /dev/null && { bad "a second SIGINT did not end the run"; kill -9 "$pid"; } || ok
wait "$pid" 2> /dev/null
kill "$holder" 2> /dev/null
wait "$holder" 2> /dev/null

# One request delivered twice, as timeout(1) does (to the process, then to its process group)
# and Ctrl-C to a process group: two SIGINTs back to back still checkpoint, and the run resumes
# to the bytes of an uninterrupted run. (Before the one-second window, the second signal ended
# the run at once and removed its rows in 4 of 5 trials: the two may also arrive as one.)
rm -f sig.csv*
"$VARSYM" "${args[@]}" 2> sig.txt &
pid=$!
wait_stepping "$pid" sig.csv.part
kill -INT "$pid"
kill -INT "$pid"
wait "$pid"
rc=$?
if [ $rc -eq 0 ]; then echo "files_test: the run ended before the SIGINTs; not a check"
else
  [ $rc -eq 130 ] && grep -q 'stopped by SIGINT' sig.txt && [ -f sig.csv.ckpt ] && ok ||
    bad "two SIGINTs back to back: exit $rc, $(cat sig.txt)"
  "$VARSYM" run --resume sig.csv.ckpt 2> /dev/null && cmp -s sig.csv straight/sig.csv && ok ||
    bad "run resumed after two SIGINTs differs from the uninterrupted run"
fi

# --- bounded reads ------------------------------------------------------------------------------
expect_error 2 "resume /dev/zero" "cannot read checkpoint '/dev/zero': not a regular file" run --resume /dev/zero
expect_error 2 "resume a directory" "cannot read checkpoint '.': it is a directory" run --resume .
truncate -s 3G huge.ckpt
expect_error 2 "resume a 3 GB file" "cannot read checkpoint 'huge.ckpt': 3221225472 bytes, more" run --resume huge.ckpt
grep -q 'more than a valid checkpoint' stderr.txt && ok || bad "size message: $(cat stderr.txt)"
rm -f huge.ckpt
mkfifo endless
(yes > endless &) 2> /dev/null
expect_error 2 "resume an endless FIFO" "cannot read checkpoint 'endless': not a regular file" run --resume endless
pkill -f '^yes$' 2> /dev/null
for f in /dev/zero /dev/urandom; do
  expect_error 2 "config '$f'" "cannot read config file '$f': not a regular file" run --config "$f"
done
expect_error 2 "config '.'" "cannot read config file '.': it is a directory" run --config .
expect_error 2 "config ''" "--config needs a file name" run --config ""

# --- numbers: decimal only, correctly rounded, whole numbers as reals --------------------------
rows() { "$VARSYM" run "$@" 2> /dev/null | tail -n +2 | wc -l; }
[ "$(rows --steps-per-period 010)" -eq 11 ] && ok || bad "010 is not ten"
[ "$(rows --time 1 --steps 1e1)" -eq 11 ] && ok || bad "1e1 steps"
[ "$(rows --steps-per-period +10)" -eq 11 ] && ok || bad "+10 steps"
[ "$(rows --q0 +1)" -eq 51 ] && ok || bad "--q0 +1"
expect_error 2 "q0 '1,'" "--q0: value 2 of '1,' is empty" run --q0 1,
expect_error 2 "q0 '1,,2'" "--q0: value 2 of '1,,2' is empty" run --model double-pendulum --q0 1,,2
expect_error 2 "hexadecimal" "--steps-per-period: '0x10' is not a whole number" run --steps-per-period 0x10
# The midpoint of 1 and its successor, plus 1e-60: correctly rounded it is the successor (a
# parser through long double lands on the midpoint and rounds to even, 1).
q0=$("$VARSYM" run --q0 1.00000000000000011102230246251565404236316680908203125000001 --every 0 |
  tail -1 | cut -d, -f3)
first=$("$VARSYM" run --q0 1.00000000000000011102230246251565404236316680908203125000001 |
  sed -n 2p | cut -d, -f3)
[ "$first" = "1.0000000000000002" ] && ok || bad "over-long number read as $first (final $q0)"
printf 'stats = true\n' > s.toml
"$VARSYM" run --config s.toml > /dev/null 2> stderr.txt && grep -q 'Newton iterations' stderr.txt &&
  ok || bad "stats = true: $(cat stderr.txt)"
printf 'stats = "true"\n' > s.toml
expect_error 2 'stats = "true"' "s.toml:1: key 'stats' expects true or false" run --config s.toml
grep -q '^varsym: error: s.toml:1: ' stderr.txt && ok || bad "file:line: $(cat stderr.txt)"
head -c 10000000 /dev/zero | tr '\0' x > big.txt
printf 'model = "%s"\n' "$(cat big.txt)" > big.toml
expect_error 2 "10 MB value" "cannot read config file 'big.toml': 10000011 bytes, more than" run --config big.toml
[ "$(wc -c < stderr.txt)" -lt 2100 ] && ok || bad "10 MB value echoed: $(wc -c < stderr.txt) bytes"
rm -f big.*

# --- the energy watch: meaningless runs stop with exit 4, keeping their rows ------------------
watch() { # NAME ARGS...
  local name=$1
  shift
  rm -f w.csv*
  "$VARSYM" run "$@" -o w.csv > /dev/null 2> stderr.txt
  local rc=$?
  [ $rc -eq 4 ] && [ -e w.csv.part ] && [ ! -e w.csv ] &&
    grep -q 'relative energy error reached .* try h <= ' stderr.txt && ok ||
    bad "watch $name: exit $rc: $(cat stderr.txt)"
}
watch "kepler e = 0.99999" --model kepler --eccentricity 0.99999
watch "double pendulum h = 1000 s" --model double-pendulum --time 100000 --steps 100
watch "simpson past its stability limit" --steps-per-period 2 --periods 10
watch "pendulum q0 = 1e308" --q0 1e308
# The advice passes the same check: rerun the Simpson case with the step it proposes.
h=$(sed 's/.*try h <= \([0-9.e+-]*\).*/\1/' stderr.txt)
rm -f w.csv*
watch "simpson past its stability limit" --steps-per-period 2 --periods 10
h=$(sed 's/.*try h <= \([0-9.e+-]*\).*/\1/' stderr.txt)
steps=$(awk -v h="$h" 'BEGIN { printf "%d", 11.8034 / h + 1 }')
"$VARSYM" run --time 11.8034 --steps "$steps" -o w2.csv 2> stderr.txt && ok ||
  bad "advised h = $h ($steps steps) fails: $(cat stderr.txt)"
# Negative controls: the watch off, and every model's default run, pass.
rm -f w.csv*
"$VARSYM" run --steps-per-period 2 --periods 10 --max-energy-error 0 -o w.csv 2> /dev/null && ok ||
  bad "--max-energy-error 0 does not turn the watch off"
for m in pendulum oscillator kepler double-pendulum heavy-top chain; do
  "$VARSYM" run --model "$m" --every 0 > /dev/null 2> stderr.txt && ok ||
    bad "default $m run stopped: $(cat stderr.txt)"
done
"$VARSYM" run --scheme newmark --steps-per-period 10 --periods 5 > /dev/null 2>&1 && ok ||
  bad "the paper's Figure 2 run (Newmark, 10 steps a period) is stopped by the watch"

# --- smaller ones -----------------------------------------------------------------------------
for a in "models" "stability" "--help" "run --help"; do
  # shellcheck disable=SC2086
  "$VARSYM" $a > /dev/full 2> stderr.txt
  [ $? -eq 1 ] && grep -q 'cannot write standard output' stderr.txt && ok || bad "$a > /dev/full"
done
expect_error 2 "bench periods 1e-9" "must give between 1 and 1e10 steps a run" bench --periods 1e-9 --problems pendulum --schemes simpson
expect_error 2 "bench lobatto-x" "in 'lobatto-x', the degree after '-' must be a whole number" bench --schemes lobatto-x
grep -q 'degree after' stderr.txt && ok || bad "bench label: $(cat stderr.txt)"
expect_error 2 "stability --max 1000" "--max: must be <= 200, got '1000'" stability --max 1000
expect_error 2 "figure2 --periods 1e6" "--periods: Value 1000000 not in range 1 to 1000" paper figure2 --periods 1000000 -o f.svg
expect_error 2 "chain n 1e8" "--n: n must be a whole number, 1 <= n <= 10000000, got 100000000" run --model chain --n 1e8
# 1e7 masses with Simpson (3 GB) fit; a dense member needs 24 (s n)^2 bytes: 2e16 GB.
expect_error 2 "chain too big for memory" "chain: n = 10000000 with gauss-8 needs about 153600003 GB" run --model chain --n 1e7 --scheme gauss --degree 8
grep -q 'needs about .* GB' stderr.txt && ok || bad "memory message: $(cat stderr.txt)"
"$VARSYM" run --checkpoint-seconds 1e10 --checkpoint cs.ck -o cs.csv 2> stderr.txt && [ -e cs.ck ] &&
  ok || bad "--checkpoint-seconds 1e10: $(cat stderr.txt)"
"$VARSYM" run -o /dev/full > /dev/null 2> stderr.txt
[ $? -eq 1 ] && grep -q "cannot write '/dev/full'" stderr.txt && ok || bad "-o /dev/full: $(cat stderr.txt)"

finish
