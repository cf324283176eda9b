#!/usr/bin/env bash
# tests/cli/expression_test.sh VARSYM: `varsym run --lagrangian` (the model `lagrangian`, L typed
# as an expression). References: the built-in pendulum (the same scheme on the reduced stepper),
# the energy, which a symplectic scheme keeps bounded, and an uninterrupted run for resume.
source "$(dirname "$0")/lib.sh" "$@"

pend=(--lagrangian "0.5*m*th_dot**2 - m*w**2*(1 - cos(th))" --coordinates th
  --parameters "m=1, w=6.283185307179586")

# --- the typed pendulum steps as the built-in one (Simpson, 2 s, h = 0.01) ---------------------
# The built-in model runs Simpson's reduced stepper, the expression the general engine: the
# same scheme, so the rows agree to round-off (measured 4e-15; bound 1e-12).
"$VARSYM" run "${pend[@]}" --q0 1.5707963267948966 --time 2 --steps 200 --every 20 -o typed.csv &&
  "$VARSYM" run --model pendulum --time 2 --steps 200 --every 20 -o builtin.csv && ok ||
  bad "pendulum runs: $(cat stderr.txt 2>/dev/null)"
paste -d, typed.csv builtin.csv | awk -F, 'NR > 1 { for (c = 3; c <= 5; ++c) { d = $c - $(c + 5);
  if (d < 0) d = -d; if (d > m) m = d } } END { exit !(NR == 12 && m <= 1e-12) }' && ok ||
  bad "typed and built-in pendulum differ: $(paste -d, typed.csv builtin.csv | tail -1)"
head -1 typed.csv | grep -qx 'step,t,q,p,energy' && ok || bad "columns: $(head -1 typed.csv)"
# Negative control: another w is seen.
"$VARSYM" run --lagrangian "0.5*th_dot**2 - 39*(1 - cos(th))" --coordinates th \
  --q0 1.5707963267948966 --time 2 --steps 200 --every 20 -o other.csv &&
  ! cmp -s <(cut -d, -f3 other.csv) <(cut -d, -f3 builtin.csv) && ok || bad "negative control"

# --- a config file gives the same run ----------------------------------------------------------
cat > typed.toml <<'TOML'
lagrangian = "0.5*m*th_dot**2 - m*w**2*(1 - cos(th))"
coordinates = "th"
parameters = "m=1, w=6.283185307179586"
q0 = [1.5707963267948966]
time = 2.0
steps = 200
every = 20
TOML
"$VARSYM" run --config typed.toml -o config.csv && cmp -s config.csv typed.csv && ok ||
  bad "config run differs: $(cat stderr.txt 2>/dev/null)"

# --- two coordinates, gauss-3, killed and resumed bit for bit ----------------------------------
dp=(run --lagrangian "0.5*(m1+m2)*th1_dot**2 + 0.5*m2*th2_dot**2 + m2*th1_dot*th2_dot*cos(th1-th2)
  + (m1+m2)*g*cos(th1) + m2*g*cos(th2)" --coordinates th1,th2 --parameters m1=1,m2=1,g=9.81
  --q0 1,0.5 --scheme gauss --degree 3 --time 20 --steps 200000 --every 1000)
"$VARSYM" "${dp[@]}" -o straight.csv || bad "double pendulum: $(cat stderr.txt)"
"$VARSYM" "${dp[@]}" -o resumed.csv --checkpoint dp.ckpt --checkpoint-every 20000 &
pid=$!
for _ in $(seq 200); do [ -e dp.ckpt ] && break; sleep 0.05; done
kill -KILL "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
[ -e dp.ckpt ] && "$VARSYM" run --resume dp.ckpt 2>/dev/null; cmp -s straight.csv resumed.csv && ok ||
  bad "resumed run differs from the straight one"
awk -F, 'NR == 2 { e = $7 } NR > 2 { d = $7 - e; if (d < 0) d = -d; if (d > m) m = d }
  END { exit !(m < 1e-6 * (e < 0 ? -e : e)) }' straight.csv && ok || bad "double pendulum energy"

# --- a damping force: E falls, and E - E0 - W (column 8) stays at the scheme's error ----------
# Simpson, h = 0.01, 10 s: measured 5e-12; bound 1e-9. Columns: 5 energy, 6 work, 7 balance.
"$VARSYM" run --lagrangian "0.5*q_dot**2 + cos(q)" --parameters c=0.1 --force "-c*q_dot" --q0 1 \
  --time 10 --steps 1000 --every 100 -o damped.csv || bad "damped run: $(cat stderr.txt)"
head -1 damped.csv | grep -qx 'step,t,q,p,energy,work,energy_balance' && ok || bad "damped columns"
awk -F, 'NR == 2 { e = $5 } NR > 1 { b = $7; if (b < 0) b = -b; if (b > m) m = b }
  END { exit !(m < 1e-9 && $5 - e < -0.2) }' damped.csv && ok || bad "damped balance: $(tail -1 damped.csv)"
expect_error 2 "force of the wrong size" "--force: 2 components for the Lagrangian's 1 coordinates" run --lagrangian "0.5*q_dot**2" --force "-q_dot,0" -o out.csv

# --- bad input: one line, exit 2, nothing written ----------------------------------------------
expect_error 2 "parse error" "--lagrangian: expected ')' to close the '(' of column 16 at" run --lagrangian "0.5*q_dot**2 - (q" -o out.csv
grep -q 'at column 18' stderr.txt && ok || bad "parse error column: $(cat stderr.txt)"
expect_error 2 "unknown name" "--lagrangian: unknown name 'k' at column 5 of" run --lagrangian "0.5*k*q_dot**2" -o out.csv
grep -q "unknown name 'k'" stderr.txt && ok || bad "unknown name: $(cat stderr.txt)"
expect_error 2 "singular mass" "lagrangian: the mass matrix d2L/dqdot2 is singular or not" run --lagrangian "q**2*q_dot**2" -o out.csv
grep -q 'singular' stderr.txt && ok || bad "singular: $(cat stderr.txt)"
expect_error 2 "no expression" "--model lagrangian needs --lagrangian EXPR" run --model lagrangian -o out.csv
expect_error 2 "bad parameters" "--parameters: 'k' is not NAME=NUMBER" run --lagrangian "0.5*k*q_dot**2" --parameters k -o out.csv
expect_error 2 "empty coordinate" "--coordinates: empty entry in 'q,'" run --lagrangian "0.5*q_dot**2" --coordinates q, -o out.csv
expect_error 2 "repeated name" "--lagrangian: the name 'q' is given twice" run --lagrangian "0.5*q_dot**2" --coordinates q,q -o out.csv
expect_error 2 "other model's option" "--eccentricity is a parameter of --model kepler, not of --model lagrangian" run --lagrangian "0.5*q_dot**2" --eccentricity 0.5 -o out.csv
# An L that depends on t takes the energy watch on E - W (W = -integral of dL/dt): accepted.
"$VARSYM" run --lagrangian "0.5*q_dot**2*exp(t)" --q0 0 --v0 1 --max-energy-error 0.1 --time 1 \
  --steps 100 -o timed.csv 2> stderr.txt && head -1 timed.csv | grep -q ',energy_balance$' && ok ||
  bad "watch on a timed L: $(cat stderr.txt)"
# --- size guard: a typed chain of 2000 masses would take minutes and GBs to differentiate -----
# (measured 0.7 s at d = 200, growing as d^2 times the text's length): refused at once, with the
# estimate. Control: the same chain of 100 masses runs.
chain_l() { awk -v d="$1" 'BEGIN { for (i = 0; i < d; i++) printf "%s0.5*x%d_dot**2", (i ? " + " : ""), i
  printf " - ("; for (i = 0; i + 1 < d; i++) printf "%s0.5*(x%d - x%d)**2", (i ? " + " : ""), i + 1, i
  printf ")" }'; }
chain_c() { awk -v d="$1" 'BEGIN { for (i = 0; i < d; i++) printf "%sx%d", (i ? "," : ""), i }'; }
expect_error 2 "typed chain of 2000" "--lagrangian: a Lagrangian of 2000 coordinates typed in" run --lagrangian "$(chain_l 2000)" --coordinates "$(chain_c 2000)" \
  -o out.csv
grep -q "would take about" stderr.txt && ok || bad "size guard: $(cut -c1-200 stderr.txt)"
"$VARSYM" run --lagrangian "$(chain_l 100)" --coordinates "$(chain_c 100)" --q0 "1$(printf ',0%.0s' $(seq 99))" \
  --time 0.1 --steps 10 --every 0 -o chain100.csv 2> stderr.txt && [ "$(wc -l < chain100.csv)" -eq 2 ] &&
  ok || bad "typed chain of 100: $(cut -c1-200 stderr.txt)"

# --- NaN during a step: exit 3, the cause named, the rows before it kept ------------------------
"$VARSYM" run --lagrangian "0.5*q_dot**2 + 1/sqrt(q)" --q0 1 --time 10 --steps 1000 \
  --max-energy-error 0 -o nan.csv 2> stderr.txt
rc=$?
[ "$rc" -eq 3 ] && grep -q 'NaN' stderr.txt && [ -s nan.csv.part ] && [ ! -e nan.csv ] && ok ||
  bad "NaN step: exit $rc, $(cat stderr.txt)"

# --- ensembles of a typed Lagrangian -------------------------------------------------------
# The oscillator L = x_dot^2/2 - k x^2/2 over t = pi: x(pi) = q0 cos(sqrt(k) pi). Members over
# q0_1 and over the parameter k: k = 1 gives -q0, k = 4 gives +q0 (a k ignored would give -q0
# for both: the negative control). Simpson at h = pi/1000: error ~ (h omega)^4 ~ 1e-10.
osc=(--model lagrangian --lagrangian "0.5*x_dot**2 - 0.5*k*x**2" --coordinates x --parameters k=1
  --time 3.141592653589793 --steps 1000)
"$VARSYM" ensemble "${osc[@]}" --grid q0_1=0.5:1:2 --grid k=1:4:2 -o lens.csv 2> lens.log ||
  bad "lagrangian ensemble: $(cat lens.log)"
head -1 lens.csv | grep -q '^member,q0_1,k,status,steps,t,q_1,p_1,' && ok || bad "header: $(head -1 lens.csv)"
awk -F, 'NR > 1 { want = ($3 == 1 ? -$2 : $2); d = $7 - want; if (d < 0) d = -d
  if ($4 != "completed" || d > 1e-8) bad++; n++ } END { exit !(n == 4 && bad == 0) }' lens.csv &&
  ok || bad "lagrangian ensemble members: $(cat lens.csv)"
# A member ends where `varsym run` of the same L ends (the same engine: bit-identical).
"$VARSYM" run "${osc[@]}" --q0 0.5 --every 0 -o lrun.csv 2> /dev/null || bad "lagrangian run"
[ "$(tail -1 lrun.csv | cut -d, -f3-4)" = "$(awk -F, '$1 == 0 { print $7 "," $8 }' lens.csv)" ] &&
  ok || bad "ensemble member 0 $(sed -n 2p lens.csv) vs run $(tail -1 lrun.csv)"
# Another L on the same output is another ensemble: the stopped one's journal is refused, not
# continued (the journal's first line names the expressions, not only the model).
long=(--coordinates x --parameters k=1 --time 1 --steps 100000 --grid q0_1=0:1:400 --threads 1
  -o lother.csv)
"$VARSYM" ensemble --model lagrangian --lagrangian "0.5*x_dot**2 - 0.5*k*x**2" "${long[@]}" \
  2> /dev/null &
pid=$!
for _ in $(seq 200); do [ -s lother.csv.journal ] && [ "$(wc -l < lother.csv.journal)" -gt 2 ] && break
  sleep 0.05; done
kill -TERM "$pid" 2> /dev/null
wait "$pid" 2> /dev/null
[ -s lother.csv.journal ] && ok || bad "the stopped ensemble kept no journal"
expect_error 2 "another Lagrangian's journal" "./lother.csv.journal belongs to another ensemble" ensemble --model lagrangian \
  --lagrangian "0.5*x_dot**2 - 0.5*k*x**2 - x**4" "${long[@]}"
# A member of an L that depends on t reports the error of E - W (W = -integral of dL/dt), the
# scheme's: below 1e-5 relative, where E itself grows by more than 10 % (failures_test.sh).
"$VARSYM" ensemble --model lagrangian --lagrangian "0.5*x_dot**2 - 0.5*(1 + 0.5*t)*x**2" \
  --coordinates x --grid q0_1=1:2:2 --time 10 --steps 1000 -o ltens.csv 2> err.txt &&
  head -1 ltens.csv | grep -q '^member,q0_1,status,steps,t,q_1,p_1,max_energy_error,' &&
  awk -F, 'NR > 1 { if ($3 != "completed" || !($8 < 1e-5)) bad++; n++ }
    END { exit !(n == 2 && bad == 0) }' ltens.csv && ok || bad "L(t) ensemble: $(cat ltens.csv err.txt)"

# --- sections and converge of a typed Lagrangian ---------------------------------------------
# The oscillator with k = 4 (omega = 2) from q0 crosses x = 0 upwards at t_n = (3 pi/2 + 2 pi n)/2
# with p = 2 q0 (exact solution): six crossings in 20 s. Gauss-2 (order 4) at h = 0.01: phase
# error ~ (h omega)^4 omega t / 720 ~ 1e-8 at t = 20; bound 1e-6.
sosc=(--model lagrangian --lagrangian "0.5*x_dot**2 - 0.5*k*x**2" --coordinates x --parameters k=4
  --time 20 --steps 2000 --scheme gauss --degree 2)
"$VARSYM" section "${sosc[@]}" --grid q0_1=0.5:1:2 --plane q1=0 -o lsec.csv 2> lsec.log ||
  bad "lagrangian section: $(cat lsec.log)"
awk -F, -v pi=3.141592653589793 'NR > 1 { dt = $4 - (1.5 * pi + 2 * pi * $3) / 2; dp = $6 - 2 * $2
  if (dt < 0) dt = -dt; if (dp < 0) dp = -dp; if (dt > 1e-6 || dp > 1e-6 || $5 > 1e-9) bad++; n++ }
  END { exit !(n == 12 && bad == 0) }' lsec.csv && ok || bad "lagrangian crossings: $(cat lsec.csv)"
# Henon-Heiles typed as L against the built-in model's section (Simpson's reduced stepper, the
# same discrete map): from y = 0.1, p_x = 0.4 (the built-in sets p_x from E = 0.08 + 0.005 -
# 0.001/3), the 32 crossings of x = 0 in 200 time units agree to 1e-11 (measured 2.8e-14).
"$VARSYM" section --model henon-heiles --set energy=0.08466666666666667 --grid q0_2=0.1:0.1:1 \
  --plane q1=0 --time 200 --steps 20000 -o hhb.csv 2> /dev/null &&
  "$VARSYM" section --model lagrangian --coordinates x,y --grid q0_2=0.1:0.1:1 \
    --lagrangian "0.5*(x_dot**2+y_dot**2) - 0.5*(x**2+y**2) - x**2*y + y**3/3" \
    --grid p0_1=0.4:0.4:1 --plane q1=0 --time 200 --steps 20000 -o hht.csv 2> /dev/null &&
  paste -d, <(cut -d, -f4- hhb.csv) <(cut -d, -f5- hht.csv) | awk -F, 'NR > 1 {
    for (i = 1; i <= 5; ++i) { d = $i - $(i + 5); if (d < 0) d = -d; if (d > m) m = d } n++ }
    END { exit !(n == 32 && m <= 1e-11) }' && ok || bad "typed Henon-Heiles section: $(head -3 hht.csv)"
# converge: a quartic oscillator (no exact solution in the model: against gauss-8) from
# --set q0_1=1; Simpson's fitted order 4, Newmark's 2 (the control: the orders differ).
quartic=(--model lagrangian --lagrangian "0.5*x_dot**2 - 0.25*x**4" --coordinates x --set q0_1=1
  --time 10 --steps 50,100,200,400)
for want in "simpson 4" "newmark 2"; do
  read -r scheme order <<< "$want"
  "$VARSYM" converge "${quartic[@]}" --scheme "$scheme" > lconv.txt 2> lconv.log &&
    awk -v p="$order" '$1 == "fitted" { f = 1; exit !($3 > p - 0.3 && $3 < p + 0.3) }
      END { if (!f) exit 1 }' lconv.txt && ok ||
    bad "lagrangian converge $scheme: $(cat lconv.txt lconv.log)"
done
expect_error 2 "converge: a start key past d" "'q0_2' is not a key of lagrangian; its keys: q0_1 p0_1" converge "${quartic[@]}" --set q0_2=1
expect_error 2 "converge: --lagrangian with another model" "--lagrangian is for --model lagrangian, not 'kepler'" converge --model kepler \
  --lagrangian "0.5*x_dot**2" --set eccentricity=0.5
expect_error 2 "--lagrangian with another model" "--lagrangian is for --model lagrangian, not 'pendulum'" ensemble --model pendulum --lagrangian "0.5*q_dot**2" \
  --grid q0_1=0:1:2 -o out.csv
expect_error 2 "lagrangian ensemble without L" "--model lagrangian needs --lagrangian EXPR" ensemble --model lagrangian --grid q0_1=0:1:2 -o out.csv

# --predictor forces on a separable typed L (the separable steppers take it; it was refused),
# refused where L runs the general engine.
"$VARSYM" run --lagrangian "0.5*q_dot^2 - 0.5*q^2" --q0 1 --time 10 --steps 100 --scheme gauss \
  --degree 4 --iteration fixed-point --predictor forces -o sep.csv 2> sep.err && ok ||
  bad "--predictor forces on a separable L: $(cat sep.err)"
expect_error 2 "--predictor forces, general engine" "lagrangian: the predictors 'previous' and 'forces' are for" run --lagrangian "0.5*q_dot^2*(1+q^2) - 0.5*q^2" \
  --q0 1 --time 10 --steps 100 --predictor forces -o out.csv

finish
