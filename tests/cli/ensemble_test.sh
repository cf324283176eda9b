#!/usr/bin/env bash
# tests/cli/ensemble_test.sh VARSYM: `varsym ensemble`. References: a member's final state against
# `varsym run` from the same initial state (another driver of the same stepper: bit-identical);
# the file written with 1 and 2 threads (byte-identical); an ensemble killed with SIGKILL and
# restarted against one that was not (byte-identical, no member twice); the event time against
# the trajectory's own sign change; and the errors (exit 2, one line).
source "$(dirname "$0")/lib.sh" "$@"

hh=(ensemble --model henon-heiles --set energy=0.125 --grid q0_2=-0.4:0.6:20 --grid p0_2=-0.4:0.4:20
  --time 100 --steps 2000)

# --- 1 and 2 threads write the same file; one row per member, in member order -----------------
"$VARSYM" "${hh[@]}" --threads 1 -o one.csv 2> /dev/null &&
  "$VARSYM" "${hh[@]}" --threads 2 -o two.csv 2> /dev/null && cmp -s one.csv two.csv && ok ||
  bad "1 and 2 threads differ"
head -1 one.csv | grep -qx 'member,q0_2,p0_2,status,steps,t,q_1,q_2,p_1,p_2,max_energy_error,lyapunov,mean_megno,event_time,cause' &&
  ok || bad "header: $(head -1 one.csv)"
awk -F, 'NR > 1 && $1 != NR - 2 { exit 1 } END { exit !(NR == 401) }' one.csv && ok ||
  bad "rows are not members 0..399 in order"
[ ! -e one.csv.journal ] && ok || bad "the journal was not removed"
# Outside the energy surface: invalid, with the reason; inside: completed.
awk -F, '$1 == 0 { exit !($4 == "invalid" && $15 ~ /outside the energy surface/) }' one.csv && ok ||
  bad "member 0 should be invalid: $(sed -n 2p one.csv)"

# --- a member's final state is the one `varsym run` reaches from its initial state -------------
# Member 210: q0_2 = -0.4 + 10/19 · 1.0 (row 10), p0_2 = -0.4 + 10/19 · 0.8 (column 10).
row=$(awk -F, '$1 == 210' one.csv)
y=$(echo "$row" | cut -d, -f2)
py=$(echo "$row" | cut -d, -f3)
"$VARSYM" run --model henon-heiles --energy 0.125 --q0 "0,$y" --p0 "0,$py" --time 100 \
  --steps 2000 --every 0 -o single.csv 2> /dev/null || bad "run from member 210: $(cat stderr.txt)"
[ "$(tail -1 single.csv | cut -d, -f3-6)" = "$(echo "$row" | cut -d, -f7-10)" ] && ok ||
  bad "member 210 ends at $(echo "$row" | cut -d, -f7-10), run at $(tail -1 single.csv | cut -d, -f3-6)"
# Its chaos indicators are numbers, and the energy error a symplectic scheme's (< 1e-4 here).
echo "$row" | awk -F, '{ exit !($4 == "completed" && $11 < 1e-4 && $12 == $12 + 0 && $13 > 0) }' &&
  ok || bad "member 210: $row"

# --- killed with SIGKILL and restarted: the same file, nothing lost or twice --------------------
big=(ensemble --model henon-heiles --grid q0_2=-0.4:0.6:30 --grid p0_2=-0.4:0.4:30 --time 250
  --steps 5000)
"$VARSYM" "${big[@]}" -o straight.csv 2> /dev/null || bad "straight ensemble"
"$VARSYM" "${big[@]}" --threads 1 -o killed.csv 2> /dev/null &
pid=$!
for _ in $(seq 200); do # until the journal holds some rows (flushed every 0.25 s)
  [ -e killed.csv.journal ] && [ "$(wc -l < killed.csv.journal)" -gt 20 ] && break
  sleep 0.05
done
kill -KILL "$pid" 2> /dev/null
wait "$pid" 2> /dev/null
[ ! -e killed.csv ] && [ -e killed.csv.journal ] && ok || bad "the killed ensemble should leave only its journal"
done_rows=$(($(wc -l < killed.csv.journal) - 1))
cp killed.csv.journal saved.journal
"$VARSYM" "${big[@]}" -o killed.csv 2> resume.txt && cmp -s straight.csv killed.csv && ok ||
  bad "the restarted ensemble differs from the straight one"
grep -q "resuming, $done_rows of 900 members already done" resume.txt && ok ||
  bad "resume message: $(cat resume.txt) (journal had $done_rows rows)"
# --- one SIGINT: said what it waits for, stopped within a second (the members in flight stop
# after their current step, not written), then the same command finishes the same file --------
long=(ensemble --model henon-heiles --grid energy=0.05:0.1:4 --time 1e6 --steps 100000000)
"$VARSYM" "${long[@]}" -o stopped.csv 2> sigint.txt &
pid=$!
sleep 1
sent=$(date +%s%N)
kill -INT "$pid"
wait "$pid"
rc=$?
took=$((($(date +%s%N) - sent) / 1000000))
[ $rc -eq 130 ] && [ $took -lt 1000 ] && ok || bad "SIGINT: exit $rc after $took ms"
grep -q "^varsym: SIGINT: stopping once the members in flight finish their current step" sigint.txt &&
  ok || bad "no line saying what SIGINT waits for: $(tr '\r' '\n' < sigint.txt)"
[ ! -e stopped.csv ] && [ "$(grep -c ',completed' stopped.csv.journal)" -eq 0 ] && ok ||
  bad "a member stopped in flight was written as completed"
# A journal cut in the middle of a row (a kill during a write): the partial row is redone.
{ cat saved.journal; printf '899,0.6,0.4,compl'; } > cut.csv.journal
"$VARSYM" "${big[@]}" -o cut.csv 2> /dev/null && cmp -s straight.csv cut.csv && ok ||
  bad "a journal with a cut row"
# A journal of another ensemble is refused (exit 2) and left alone; so is one of a varsym before
# row checksums (first line "# varsym ensemble: ...").
{ echo "# varsym ensemble journal 2: another"; echo "0,1 #00000000"; } > other.csv.journal
cp other.csv.journal other.keep
expect_error 2 "another ensemble's journal" "./other.csv.journal belongs to another ensemble" "${hh[@]}" -o other.csv
cmp -s other.csv.journal other.keep && ok || bad "the other journal was changed"
{ echo "# varsym ensemble: another"; echo "0,1"; } > other.csv.journal
expect_error 2 "an old journal" "./other.csv.journal was written by an older varsym, without" "${hh[@]}" -o other.csv
grep -q "older varsym" stderr.txt && ok || bad "old journal message: $(cat stderr.txt)"

# --- journal rows carry their CRC-32: a forged or damaged row is computed again, never copied ---
# Reference for the checksum: zlib's CRC-32 of the row (Python), the same polynomial as Boost's.
crc_rows() { /usr/bin/python3 -c 'import sys, zlib
for line in sys.stdin.read().splitlines(): print("%s #%08x" % (line, zlib.crc32(line.encode())))'; }
[ "$(sed -n 2p saved.journal)" = "$(sed -n 2p saved.journal | sed 's/ #[0-9a-f]*$//' | crc_rows)" ] &&
  ok || bad "journal row checksum: $(sed -n 2p saved.journal)"
# Forged: member 899's row with q_1 = 42, once without a checksum, once with a wrong one; damaged:
# a digit put into row 3. Each is ignored and its member computed again: the straight file.
forged=$(tail -1 straight.csv | awk -F, -v OFS=, '{ $7 = 42; print }')
{ head -2 saved.journal; sed -n 3p saved.journal | sed 's/,/,0/'
  sed -n '4,$p' saved.journal; echo "$forged"; echo "$forged #00000000"; } > forged.csv.journal
"$VARSYM" "${big[@]}" -o forged.csv 2> forged.txt && cmp -s straight.csv forged.csv && ok ||
  bad "forged journal rows were copied: $(diff straight.csv forged.csv | head -3)"
grep -q "3 damaged journal rows ignored" forged.txt && ok || bad "forged rows: $(cat forged.txt)"

# --- killed during the final write: OUTPUT.part beside complete journals; the same command again
# writes the output. A stray OUTPUT.part without a journal is refused before any member runs. ---
{ head -1 saved.journal; tail -n +2 straight.csv | crc_rows; } > last.csv.journal
head -c 1000 straight.csv > last.csv.part
"$VARSYM" "${big[@]}" -o last.csv 2> last.txt && cmp -s straight.csv last.csv &&
  [ ! -e last.csv.part ] && [ ! -e last.csv.journal ] && ok || bad "resume after the final write: $(cat last.txt)"
grep -q "resuming, 900 of 900 members already done" last.txt && ok || bad "final-write resume: $(cat last.txt)"
# Rows in any order (here reversed: 900 runs of one row each) are merged into member order.
{ head -1 saved.journal; tail -n +2 straight.csv | tac | crc_rows; } > reversed.csv.journal
"$VARSYM" "${big[@]}" -o reversed.csv 2> /dev/null && cmp -s straight.csv reversed.csv && ok ||
  bad "a journal in reverse order: $(diff straight.csv reversed.csv | head -3)"
echo "mine" > stray.csv.part
"$VARSYM" "${big[@]}" -o stray.csv 2> stray.txt
rc=$?
[ "$rc" -eq 2 ] && [ "$(wc -l < stray.txt)" -eq 1 ] && grep -q "stray.csv.part' exists" stray.txt &&
  ! grep -q "varsym run --resume" stray.txt && [ "$(cat stray.csv.part)" = mine ] &&
  [ ! -e stray.csv.journal ] && [ ! -e stray.csv ] && ok || bad "stray .part: exit $rc, $(cat stray.txt)"

# --- one ensemble per output: a second one is refused while the first runs, and one started as
# the first finishes is refused or starts afresh; never exit 1, never a journal left behind -----
"$VARSYM" "${big[@]}" --threads 1 -o busy.csv 2> /dev/null &
pid=$!
for _ in $(seq 200); do [ -s busy.csv.journal ] && break; sleep 0.05; done
expect_error 2 "a second ensemble of the output" "busy.csv.journal is in use by another running ensemble of" "${big[@]}" -o busy.csv
grep -q "in use by another running ensemble" stderr.txt && ok || bad "busy: $(cat stderr.txt)"
kill -KILL "$pid" 2> /dev/null
wait "$pid" 2> /dev/null
small=(ensemble --model pendulum --grid q0_1=0:1:200 --time 1 --steps 100)
"$VARSYM" "${small[@]}" -o race_ref.csv 2> /dev/null
for i in $(seq 12); do
  "$VARSYM" "${small[@]}" -o race.csv 2> race1.txt &
  pid=$!
  sleep "0.0$((i % 10))"
  "$VARSYM" "${small[@]}" -o race.csv 2> race2.txt
  rc2=$?
  wait "$pid"
  rc1=$?
  { [ "$rc1" -eq 0 ] || [ "$rc1" -eq 2 ]; } && { [ "$rc2" -eq 0 ] || [ "$rc2" -eq 2 ]; } &&
    [ $((rc1 + rc2)) -lt 4 ] && cmp -s race.csv race_ref.csv && ! ls race.csv.journal* > /dev/null 2>&1 ||
    { bad "start/finish race $i: exits $rc1 and $rc2: $(cat race1.txt race2.txt)"; break; }
done
ok

# --- memory bounded by the work in flight, not by the output ----------------------------------
# 600 000 one-step members write about 80 MB. The journal is streamed into the output in member
# order, and no list of members is made: the peak resident memory (the children's ru_maxrss)
# stays under half the output's size (measured 10-16 MB of 80 MB; once 31). Negative control:
# merging in memory, as before, held the journal and the body at once: 186 MB, 2.3x the output.
peak_kb=$(/usr/bin/python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], check=True, stderr=subprocess.DEVNULL)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)' "$VARSYM" ensemble --model pendulum \
  --grid q0_1=0.1:1:600 --grid omega=1:2:1000 --steps 1 --no-indicators -o mem.csv)
out_kb=$(($(stat -c %s mem.csv) / 1024))
# Under AddressSanitizer (make test-sanitize-cli sets VARSYM_SANITIZED) the peak measures ASan's
# shadow memory and quarantine (490 MB here), not varsym: only the rows are checked there.
limit_kb=$((out_kb / 2))
[ -n "${VARSYM_SANITIZED:-}" ] && limit_kb=$((1 << 40))
[ "$(wc -l < mem.csv)" -eq 600001 ] && [ -n "$peak_kb" ] && [ "$peak_kb" -lt $limit_kb ] && ok ||
  bad "memory: peak ${peak_kb} KiB for an output of ${out_kb} KiB"
awk -F, 'NR > 1 && $1 != NR - 2 { exit 1 }' mem.csv && ok || bad "memory: rows out of order"

# --- events: the double pendulum's second link flips -------------------------------------------
printf 'q0_1,q0_2\n2.0,2.5\n0.1,0.1\n' > dp.csv
"$VARSYM" ensemble --model double-pendulum --members dp.csv --event 'q2^2 - pi^2' --time 10 \
  --steps 5000 -o flips.csv 2> /dev/null || bad "double pendulum ensemble: $(cat stderr.txt)"
te=$(awk -F, '$1 == 0 && $4 == "event" { print $14 }' flips.csv)
awk -F, '$1 == 1 { exit !($4 == "completed" && $14 == "nan") }' flips.csv && ok ||
  bad "the small swing should not flip: $(sed -n 3p flips.csv)"
# The trajectory of `varsym run` crosses |th2| = pi between the two steps around te.
"$VARSYM" run --model double-pendulum --q0 2.0,2.5 --time 10 --steps 5000 -o dp_run.csv 2> /dev/null
awk -F, -v te="$te" 'NR > 2 && !found { s = $4 * $4 - 3.141592653589793 ^ 2
  if (s >= 0) { found = 1; exit !(te > prev && te <= $2) } prev = $2 }
  END { if (!found) exit 1 }' dp_run.csv && ok || bad "event time $te is not at the run's flip"

# --- failed and invalid members are reported in their rows; the ensemble goes on ---------------
printf 'mass,omega\n1,6.28\n-1,6.28\n' > pm.csv
"$VARSYM" ensemble --model pendulum --members pm.csv -o pm_out.csv 2> /dev/null &&
  awk -F, 'NR == 3 { exit !($4 == "invalid" && $13 ~ /mass/) }' pm_out.csv && ok ||
  bad "invalid member: $(cat pm_out.csv)"
"$VARSYM" ensemble --model pendulum --grid q0_1=3.0:3.1:2 --time 10 --steps 4 -o pf.csv \
  2> /dev/null && [ "$(grep -c ',failed,' pf.csv)" -eq 2 ] && grep -q 'Newton did not converge' pf.csv &&
  ok || bad "failed members: $(cat pf.csv)"

# --- the heat map ------------------------------------------------------------------------------
"$VARSYM" "${hh[@]}" -o map.csv --plot map.png 2> /dev/null && [ -s map.png ] && [ -s map.gp ] &&
  [ -s map.grid.csv ] && ok || bad "heat map: $(ls map*)"

# --- MPI: 1, 2 and 4 ranks write the file 1 and 2 threads wrote (a build with MPI) ------------
if ldd "$VARSYM" | grep -q libmpi && command -v mpirun > /dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  for n in 1 2 4; do
    mpirun -np $n "$VARSYM" "${hh[@]}" --threads 1 -o mpi$n.csv > mpi$n.log 2>&1 &&
      cmp -s one.csv mpi$n.csv && ok || bad "mpirun -np $n differs: $(tail -2 mpi$n.log)"
  done
  ls mpi4.csv.journal* > /dev/null 2>&1 && bad "rank journals left behind" || ok
  # A plain ensemble and an mpirun one of the same output exclude each other, either way round.
  "$VARSYM" "${big[@]}" --threads 1 -o both.csv 2> /dev/null &
  pid=$!
  for _ in $(seq 200); do [ -s both.csv.journal ] && break; sleep 0.05; done
  mpirun -np 2 "$VARSYM" "${big[@]}" --threads 1 -o both.csv > both.log 2>&1
  rc=$?
  [ "$rc" -eq 2 ] && grep -q "in use by another running ensemble" both.log && ok ||
    bad "mpirun beside a plain ensemble: exit $rc, $(tail -3 both.log)"
  kill -KILL "$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
  rm -f both.csv.journal*
  mpirun -np 2 "$VARSYM" "${big[@]}" --threads 1 -o both.csv > /dev/null 2>&1 &
  pid=$!
  for _ in $(seq 200); do [ -s both.csv.journal.1 ] && break; sleep 0.05; done
  expect_error 2 "a plain ensemble beside mpirun" "both.csv.journal is in use by another running ensemble of" "${big[@]}" -o both.csv
  kill -TERM "$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
else
  skip "MPI (this varsym is built without MPI, or mpirun is missing)"
fi

# --- Poincaré sections: on the plane, on the energy surface, the same for any threads ----------
sec=(section --model henon-heiles --set energy=0.125 --grid q0_2=-0.3:0.5:5 --plane q1=0
  --direction + --crossings 50 --time 2000 --steps 40000)
"$VARSYM" "${sec[@]}" --threads 1 -o sec1.csv 2> sec.log && "$VARSYM" "${sec[@]}" --threads 2 \
  -o sec2.csv 2> /dev/null && cmp -s sec1.csv sec2.csv && ok || bad "section threads: $(cat sec.log)"
head -1 sec1.csv | grep -qx 'member,q0_2,crossing,t,q_1,q_2,p_1,p_2' && ok || bad "section header"
# 5 orbits × 50 crossings; each point has x = 0 to round-off (Newton on the step map), p_x > 0,
# and the energy of the orbit (Simpson at h = 0.05 keeps it to ~1e-8).
awk -F, 'NR > 1 { n++; x = $5 < 0 ? -$5 : $5; if (x > 1e-12 || $7 <= 0) bad++
  e = 0.5 * ($7 * $7 + $8 * $8) + 0.5 * ($5 * $5 + $6 * $6) + $5 * $5 * $6 - $6 * $6 * $6 / 3
  d = e - 0.125; if (d < 0) d = -d; if (d > 1e-6) bad++ }
  END { exit !(n == 250 && bad == 0) }' sec1.csv && ok || bad "section points: $(sed -n 2,3p sec1.csv)"
grep -q '5 orbits, 250 crossings, 0 invalid, 0 failed' sec.log && ok || bad "section summary: $(cat sec.log)"
"$VARSYM" "${sec[@]}" -o secp.csv --plot secp.png 2> /dev/null && [ -s secp.png ] && ok ||
  bad "section plot"
# A section streams its rows as its members finish: 600 000 crossings (48 MB) peak under half
# the output's size (measured 10 MB; holding the rows to the end, as before, took 100 MB).
peak_kb=$(/usr/bin/python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], check=True, stderr=subprocess.DEVNULL)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)' "$VARSYM" section --model pendulum \
  --grid q0_1=0.5:1.5:6000 --plane q1=0 --direction + --crossings 100 --time 200 --steps 10000 \
  -o secm.csv)
out_kb=$(($(stat -c %s secm.csv) / 1024))
limit_kb=$((out_kb / 2))
[ -n "${VARSYM_SANITIZED:-}" ] && limit_kb=$((1 << 40)) # ASan's memory, not varsym's
[ "$(wc -l < secm.csv)" -eq 600001 ] && [ -n "$peak_kb" ] && [ "$peak_kb" -lt $limit_kb ] &&
  awk -F, 'NR > 1 && ($1 < m || ($1 == m && $3 != c + 1 && NR > 2)) { bad++ } NR > 1 { m = $1; c = $3 }
    END { exit bad > 0 }' secm.csv && ok || bad "section memory: peak ${peak_kb} KiB for ${out_kb} KiB"
expect_error 2 "bad plane" "--plane needs qI=VALUE or pI=VALUE with I from 1 to 2, got" section --model henon-heiles --grid q0_2=0:0.1:2 --plane x1=0 -o out.csv
expect_error 2 "no dense output" "varsym section needs a stepper with dense output" section --model four-bar --grid torque=0:0.1:2 -o out.csv

# --- errors: one line, exit 2 ------------------------------------------------------------------
expect_error 2 "unknown key" "'z' is not a key of henon-heiles; its keys: q0_1 p0_1 q0_2" ensemble --model henon-heiles --grid z=0:1:2 -o out.csv
expect_error 2 "bad grid" "--grid needs KEY=FIRST:LAST:COUNT, got 'q0_2=0:1'" ensemble --model henon-heiles --grid q0_2=0:1 -o out.csv
expect_error 2 "zero count" "--grid q0_2: the count must be a whole number from 1 to" ensemble --model henon-heiles --grid q0_2=0:1:0 -o out.csv
expect_error 2 "grid and members" "give --grid or --members, not both" ensemble --model pendulum --grid q0_1=0:1:2 --members pm.csv -o out.csv
expect_error 2 "no members" "no members: give --grid KEY=FIRST:LAST:COUNT or --members" ensemble --model pendulum -o out.csv
expect_error 2 "no output" "--output is required" ensemble --model pendulum --grid q0_1=0:1:2
expect_error 2 "plot of one axis" "--plot draws a heat map over a grid of two --grid axes of" ensemble --model pendulum --grid q0_1=0:1:2 -o out.csv --plot p.png
expect_error 2 "bad event" "--event: unknown name 'q3' at column 1 of \"q3 + 1\"" ensemble --model pendulum --grid q0_1=0:1:2 --event 'q3 + 1' -o out.csv
expect_error 2 "unknown model" "'q0_1' is not a key of kepler; its keys: eccentricity" ensemble --model kepler --grid q0_1=0:1:2 -o out.csv
expect_error 2 "bad --set" "--set needs NAME=VALUE, got 'mass'" ensemble --model pendulum --set mass -o out.csv --grid q0_1=0:1:2
expect_error 2 "too many steps" "more than 1000000000000000 steps requested" ensemble --model pendulum --grid q0_1=0:1:1000000000 --steps 10000000 -o out.csv

# A parameter set for every member (--set) is checked once against its range: exit 2 before any
# member runs (n = 0 and dim = 0 ran every member into an error, n = 2e7 wrote 737 MB of invalid
# rows, energy = inf marked every member invalid with exit 0). Negative control: in range runs.
expect_error 2 "--set n=0" "--set n: n must be a whole number, 1 <= n <= 10000000, got 0" ensemble --model chain --set n=0 --grid q0_1=0:1:2 -o out.csv
expect_error 2 "--set n=2e7" "--set n: n must be a whole number, 1 <= n <= 10000000, got" ensemble --model chain --set n=2e7 --grid q0_1=0:1:2 -o out.csv
expect_error 2 "--set dim=-3" "--set dim: dim must be a whole number, 1 <= dim <= 10000" ensemble --model oscillator --set dim=-3 --grid q0_1=0:1:2 -o out.csv
expect_error 2 "--set dim=0" "--set dim: dim must be a whole number, 1 <= dim <= 10000" ensemble --model oscillator --set dim=0 --grid q0_1=0:1:2 -o out.csv
expect_error 2 "--set energy=inf" "--set energy: energy must be a finite number" ensemble --model henon-heiles --set energy=inf \
  --grid q0_2=0:0.1:2 -o out.csv
grep -q "^varsym: error: --set energy: energy must be" stderr.txt && ok || bad "$(cat stderr.txt)"
"$VARSYM" ensemble --model chain --set n=3 --grid q0_1=0:0.1:2 --time 0.1 --steps 10 \
  -o set_ok.csv 2> set_ok.err && ok || bad "--set n=3: $(cat set_ok.err)"

finish
