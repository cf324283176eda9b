#!/usr/bin/env bash
# tests/cli/failures_test.sh VARSYM: nothing lost, nothing silently wrong. A failure that is not
# Newton's keeps the rows and the last state as a Newton failure does; sizes that do not fit are
# refused before any work; inputs that would be misread are refused with one line naming them.
# Each case below failed before (exit 1 with every row deleted, a wrapped member count run as
# four members, a NaN event time with exit 0, ...).
source "$(dirname "$0")/lib.sh" "$@"

# no_output NAME: nothing named out.csv or out.csv.part was written (refused before any work).
no_output() { [ ! -e out.csv ] && [ ! -e out.csv.part ] && ok || bad "$1: wrote out.csv(.part)"; }

# --- a failure inside a run that is not Newton's: exit 3, rows and last state kept --------------
# L = (1 - t) x'^2 / 2 - x^2 / 2: the mass matrix vanishes at t = 1, step 1000 of 2000, where
# the row's energy cannot be evaluated: the rows of steps 0..999 are kept (1000 rows and the
# header), and the checkpoint holds step 1000, the last state the steps reached.
"$VARSYM" run --lagrangian "0.5*(1-t)*x_dot**2 - 0.5*x**2" --coordinates x --q0 1 --time 2 \
  --steps 2000 --max-energy-error 0 -o e.csv 2> err.txt
rc=$?
[ "$rc" -eq 3 ] && [ "$(wc -l < err.txt)" -eq 1 ] &&
  grep -q "step 1001 (t = 1 -> 1.001) failed: .*singular" err.txt && ok ||
  bad "singular mass matrix in a run: exit $rc, $(cat err.txt)"
[ -e e.csv.part ] && [ "$(wc -l < e.csv.part)" -eq 1001 ] && [ ! -e e.csv ] && ok ||
  bad "singular mass matrix: rows not kept ($(wc -l < e.csv.part 2> /dev/null))"
[ -e e.csv.ckpt ] && "$VARSYM" run --resume e.csv.ckpt 2> err2.txt
[ $? -eq 3 ] && grep -q "failed" err2.txt && ok || bad "resuming the failed run: $(cat err2.txt)"

# --- the energy watch follows dL/dt, not the name t --------------------------------------------
# + 0*t does not make L depend on t: at h*omega = 5 (omega = 10, h = 0.5) the energy blows up
# and the watch stops the run (exit 4), as it does without the term (the control).
for extra in "" " + 0*t" " + t - t"; do
  "$VARSYM" run --lagrangian "0.5*x_dot**2 - 50*x**2$extra" --coordinates x --q0 1 --time 50 \
    --steps 100 -o w.csv 2> err.txt
  rc=$?
  [ "$rc" -eq 4 ] && ok || bad "energy watch with L = ...$extra: exit $rc, $(cat err.txt)"
  rm -f w.csv w.csv.part
done
# An L that depends on t is watched too, on E - W with W = -integral of dL/dt: the spring
# stiffening in time at the same h*omega = 5 stops with exit 4 (before: no watch, exit 0).
"$VARSYM" run --lagrangian "0.5*x_dot**2 - 50*(1 + 0.01*t)*x**2" --coordinates x --q0 1 \
  --time 50 --steps 100 -o w.csv 2> err.txt
rc=$?
[ "$rc" -eq 4 ] && ok || bad "energy watch with L(t): exit $rc, $(cat err.txt)"
rm -f w.csv w.csv.part
# The balance itself. L = x'^2/2 - (1 + t/2) x^2/2 from x = 1 over 10 s: E = x'^2/2 + (1 + t/2)
# x^2/2 grows (dE/dt = -dL/dt = x^2/4), by more than 10 % (the control: E alone is not kept);
# E - E0 - W stays at Simpson's error, below 1e-6 at h = 0.01, and falls by 2^4 = 16 (12 to 20)
# when h is halved: the balance closes at the scheme's order.
for n in 1000 2000; do
  "$VARSYM" run --lagrangian "0.5*x_dot**2 - 0.5*(1 + 0.5*t)*x**2" --coordinates x --q0 1 \
    --time 10 --steps "$n" -o "tdep$n.csv" 2> err.txt || bad "L(t) run: $(cat err.txt)"
done
head -1 tdep1000.csv | grep -qx 'step,t,q,p,energy,work,energy_balance' && ok ||
  bad "L(t) columns: $(head -1 tdep1000.csv)"
b1=$(awk -F, 'NR > 1 { b = $7 < 0 ? -$7 : $7; if (b > m) m = b } END { if (NR > 1) printf "%.3g", m }' tdep1000.csv)
b2=$(awk -F, 'NR > 1 { b = $7 < 0 ? -$7 : $7; if (b > m) m = b } END { if (NR > 1) printf "%.3g", m }' tdep2000.csv)
numbers "L(t) energy balance" "$b1" "$b2" &&
  awk -F, -v b1="$b1" -v b2="$b2" 'NR == 2 { e0 = $5 } END { de = $5 - e0
  exit !(de > 0.1 * e0 && b1 < 1e-6 && b1 / b2 > 12 && b1 / b2 < 20) }' tdep1000.csv && ok ||
  bad "L(t) energy balance: max $b1 (h = 0.01), $b2 (h = 0.005); $(tail -1 tdep1000.csv)"
expect_error 2 "a coordinate named t" "--lagrangian: coordinate name 't' is taken by the time" run --lagrangian "0.5*t_dot**2" --coordinates t -o out.csv
expect_error 2 "a parameter named t" "--lagrangian: parameter name 't' is taken by the time" run --lagrangian "0.5*x_dot**2*t" --coordinates x \
  --parameters t=2 -o out.csv

# --- a regular L that is not quadratic in the velocities runs ----------------------------------
# L = x'^4/4 - x^2/2 from x' = 1: p = x'^3 = 1, found by Newton from x' = p where the mass matrix
# 3 x'^2 vanishes at the usual start x' = 0. Energy E = 3/4 x'^4 + x^2/2 = 0.75 at the start;
# over 10 s (several turning points, where x' = 0) it stays within 1e-3 (measured 4e-4), and
# the amplitude is the turning point of the energy, sqrt(2 E) = sqrt(1.5) = 1.22474 (to 1e-3).
"$VARSYM" run --lagrangian "0.25*x_dot**4 - 0.5*x**2" --coordinates x --q0 0 --v0 1 --time 10 \
  --steps 1000 -o quartic.csv 2> err.txt
rc=$?
[ "$rc" -eq 0 ] && awk -F, 'NR == 2 { exit !($4 == 1 && $5 == 0.75) }' quartic.csv &&
  awk -F, 'NR > 1 { e = $5 - 0.75; e = e < 0 ? -e : e; if (e > de) de = e;
    a = $3 < 0 ? -$3 : $3; if (a > amp) amp = a }
    END { d = amp - sqrt(1.5); exit !(de < 1e-3 && d < 1e-3 && d > -1e-3) }' quartic.csv && ok ||
  bad "quartic L: exit $rc, $(cat err.txt) $(sed -n 2p quartic.csv 2> /dev/null)"

# --- sizes that do not fit are refused before any work -----------------------------------------
# 7695460 * 429509837 * 5581 = 2^64 + 4 wrapped to 4 members; 2^29 * 2^29 * 64 to 0.
expect_error 2 "a grid of 2^64 + 4 members" "more than 1e9 members" ensemble --model pendulum --grid q0_1=0:1:7695460 \
  --grid p0_1=0:1:429509837 --grid mass=1:2:5581 -o out.csv
no_output "2^64 + 4 members"
expect_error 2 "a grid of 2^64 members" "more than 1e9 members" ensemble --model pendulum --grid q0_1=0:1:536870912 \
  --grid p0_1=0:1:536870912 --grid mass=1:2:64 -o out.csv
expect_error 2 "100000 threads" "--threads: Value 100000 not in range 0 to 4096" ensemble --model pendulum --grid q0_1=0:1:4 --threads 100000 \
  -o out.csv
no_output "100000 threads"

# --- inputs that would be misread ---------------------------------------------------------------
expect_error 2 "q0_01 for q0_1" "'q0_01' is not a key of pendulum; did you mean q0_1?" ensemble --model pendulum --grid q0_01=0:1:2 -o out.csv
grep -q "did you mean q0_1" stderr.txt && ok || bad "q0_01: $(cat stderr.txt)"
# A UTF-8 byte-order mark before the first key is not part of it: the same output as without.
printf '\xef\xbb\xbfq0_1,mass\n0.5,1\n1,2\n' > bom.csv
printf 'q0_1,mass\n0.5,1\n1,2\n' > plain.csv
"$VARSYM" ensemble --model pendulum --members bom.csv --time 1 --steps 10 -o b.csv 2> err.txt &&
  "$VARSYM" ensemble --model pendulum --members plain.csv --time 1 --steps 10 -o p.csv &&
  cmp -s b.csv p.csv && ok || bad "members file with a byte-order mark: $(cat err.txt)"
# An event whose value is not a number fails the member, naming why (no event at a NaN time).
"$VARSYM" ensemble --model pendulum --grid q0_1=0.5:1:2 --event "q1/0" --time 1 --steps 10 \
  -o ev.csv 2> err.txt
[ "$(awk -F, 'NR > 1 { print $3 }' ev.csv | sort -u)" = failed ] &&
  grep -q "event's value is not a finite number" ev.csv && ok ||
  bad "event q1/0: $(cat ev.csv)"
# henon-heiles' energy 1e308 is in range but gives p = inf: refused before the run.
expect_error 2 "a start that is not finite" "henon-heiles: the initial state is not finite (p0): check" run --model henon-heiles --energy 1e308 -o out.csv
no_output "a start that is not finite"

# Data the library refuses (std::invalid_argument) is bad input wherever a command lets it
# through: exit 2, not 1 (the I/O failure code) as before.
expect_error 2 "bench --schemes gauss-9" "degree must be between 1 and 8, got 9" bench --schemes gauss-9 -o out.csv
expect_error 2 "converge a chain that does not fit in memory" "n = 10000000 with gauss-8 needs about 153600003 GB, more" converge --model chain --set n=1e7 \
  --time 0.01 --steps 2,4 -o out.csv
# section --help names the models it runs (it named two of ten).
"$VARSYM" section --help | grep -q -- '--model TEXT .*kepler.*chain.*urdf' && ok ||
  bad "section --help: $("$VARSYM" section --help | grep -- '--model')"

finish
