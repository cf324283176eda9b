#!/usr/bin/env bash
# tests/cli/cli_test.sh VARSYM: the varsym tool end to end: successful runs produce what the
# README says, and every bad input gives one line on standard error, the documented exit code,
# no output file that looks complete, and leaves a file the user already had untouched.
source "$(dirname "$0")/lib.sh" "$@"

# --- bad input: exit 2 ---------------------------------------------------------------------
expect_error 2 "zero steps" "--steps-per-period: must be >= 1, got '0'" run --steps-per-period 0 -o out.csv
expect_error 2 "negative steps" "--steps-per-period: must be >= 1, got '-5'" run --steps-per-period -5 -o out.csv
expect_error 2 "fractional steps" "--steps-per-period: '2.5' is not a whole number" run --steps-per-period 2.5 -o out.csv
expect_error 2 "zero periods" "--periods: must be > 0, got '0'" run --periods 0 -o out.csv
expect_error 2 "negative periods" "--periods: must be > 0, got '-1'" run --periods -1 -o out.csv
expect_error 2 "unknown iteration" "--iteration: chord not in {newton,simplified,fixed-point,articulated}" run --iteration chord -o out.csv
expect_error 2 "unknown predictor" "--predictor: cubic not in {taylor,previous,forces}" run --predictor cubic -o out.csv
expect_error 2 "previous predictor on the general engine" "double-pendulum: the predictors 'previous' and 'forces' are" run --model double-pendulum --predictor previous -o out.csv
expect_error 2 "unknown bench solver" "--solver: unknown solver 'chord': automatic, newton" bench --solver chord --problems kepler
expect_error 2 "unknown solver after a scheme" "--schemes: in 'gauss-4/chord': unknown solver 'chord'" bench --schemes gauss-4/chord --problems kepler
expect_error 2 "zero mass" "--mass: mass must be positive, got 0" run --mass 0 -o out.csv
expect_error 2 "negative mass" "--mass: mass must be positive, got -2" run --mass -2 -o out.csv
expect_error 2 "zero omega" "--omega: omega must be positive, got 0" run --omega 0 -o out.csv
expect_error 2 "negative omega" "--omega: omega must be positive, got -6.28" run --omega -6.28 -o out.csv
expect_error 2 "NaN mass" "--mass: mass must be positive, got nan" run --mass nan -o out.csv
expect_error 2 "inf omega" "--omega: omega must be positive, got inf" run --omega inf -o out.csv
expect_error 2 "NaN q0" "--q0: value 1, 'NaN', is not finite" run --q0 NaN -o out.csv
expect_error 2 "inf p0" "--p0: value 1, '-inf', is not finite" run --p0 -inf -o out.csv
expect_error 2 "text for a number" "--mass: 'heavy' is not a number" run --mass heavy -o out.csv
expect_error 2 "text for steps" "--steps-per-period: 'many' is not a whole number" run --steps-per-period many -o out.csv
expect_error 2 "negative every" "--every: must be >= 0, got '-1'" run --every -1 -o out.csv
expect_error 2 "zero time" "--time: must be > 0, got '0'" run --time 0 --steps 10 -o out.csv
expect_error 2 "zero steps with time" "--steps: must be >= 1, got '0'" run --time 1 --steps 0 -o out.csv
expect_error 2 "time without steps" "--time requires --steps" run --time 1 -o out.csv
expect_error 2 "time with periods" "--periods excludes --time" run --time 1 --steps 10 --periods 2 -o out.csv
expect_error 2 "unknown scheme" "--scheme: euler not in {simpson,newmark,lobatto,gauss}" run --scheme euler -o out.csv
expect_error 2 "unknown option" "The following arguments were not expected: 1 --bogus" run --bogus 1 -o out.csv
expect_error 2 "unknown command" "unknown command 'frobnicate'; expected one of run, models" frobnicate
expect_error 2 "unknown paper command" "unknown command 'table2'; expected one of table1, figure1" paper table2
expect_error 2 "missing command" "A subcommand is required" paper
expect_error 2 "separatrix" "pendulum: initial state is on the separatrix" run --q0 3.141592653589793 -o out.csv
expect_error 2 "periods not giving whole steps" "--periods 0.500000 times --steps-per-period 3 is not a" run --steps-per-period 3 --periods 0.5 -o out.csv
expect_error 2 "too many steps (periods)" "more than 1000000000000000 steps requested" run --periods 1e14 -o out.csv
expect_error 2 "too many steps (time)" "more than 1000000000000000 steps requested" run --time 1 --steps 2000000000000000 -o out.csv
expect_error 2 "table1 unknown format" "--format: xml not in {text,csv}" paper table1 --format xml -o out.csv
expect_error 2 "figure bad extension" "cannot draw 'out.jpg': use a .png or .svg file name" paper figure1 -o out.jpg
expect_error 2 "figure without output" "--output is required" paper figure1
expect_error 2 "degree with simpson" "--degree applies to --scheme lobatto or gauss; simpson has" run --scheme simpson --degree 3 -o out.csv
expect_error 2 "degree with newmark" "--degree applies to --scheme lobatto or gauss; newmark has" run --scheme newmark --degree 2 -o out.csv
expect_error 2 "degree too high" "--degree: degree must be between 1 and 8, got 9" run --scheme gauss --degree 9 -o out.csv
expect_error 2 "degree zero" "--degree: must be >= 1, got '0'" run --scheme lobatto --degree 0 -o out.csv
expect_error 2 "degree not a number" "--degree: 'two' is not a whole number" run --scheme lobatto --degree two -o out.csv
expect_error 2 "converge one step count" "--steps needs at least two different step counts, e.g." converge --steps 50 -o out.csv
expect_error 2 "converge repeated step count" "--steps needs at least two different step counts, e.g." converge --steps 50,50 -o out.csv
expect_error 2 "converge zero steps" "--steps: must be >= 1, got '0'" converge --steps 0,50 -o out.csv
expect_error 2 "converge text in steps" "--steps: 'abc' is not a whole number" converge --steps 25,abc -o out.csv
expect_error 2 "converge unknown model" "--model: nosuch not in" converge --model nosuch -o out.csv
expect_error 2 "converge, a scheme for a rigid body" "--scheme and --degree do not apply to --model top: rigid" converge --model top --scheme gauss -o out.csv
expect_error 2 "converge zero periods" "--periods: must be >= 1, got '0'" converge --periods 0 -o out.csv
expect_error 2 "converge bad plot extension" "cannot draw 'out.pdf': use a .png or .svg file name" converge --plot out.pdf -o out.csv

# --- unwritable paths: exit 1 --------------------------------------------------------------
expect_error 1 "missing folder" "/no/such/dir/out.csv.part': No such file or directory" run -o "$work/no/such/dir/out.csv"
mkdir -p adir
expect_error 2 "path is a folder" "cannot write 'adir': it is a directory" run -o adir
expect_error 1 "figure in missing folder" "/no/such' does not exist" paper figure1 -o "$work/no/such/fig.png"
expect_error 1 "table1 missing folder" "/no/such/t.txt.part': No such file or directory" paper table1 -o "$work/no/such/t.txt"

# --- Newton divergence: exit 3, rows kept in out.csv.part ----------------------------------
# One Simpson step per period diverges at step 2 (tests/schemes/test_integrate.cpp).
expect_error 3 "newton diverges" "Newton's method did not converge in step 2" run --steps-per-period 1 --periods 3 --max-energy-error 0 -o out.csv
if grep -q 'step 2' stderr.txt && grep -q 'residual' stderr.txt && grep -q 'out.csv.part' stderr.txt; then ok; else
  bad "divergence message: $(cat stderr.txt)"; fi
if [ -f out.csv.part ] && [ "$(head -1 out.csv.part)" = "step,t,q,p,energy,q_exact,p_exact" ] &&
   [ "$(wc -l < out.csv.part)" -eq 3 ]; then ok; else bad "out.csv.part should hold header + steps 0, 1"; fi
rm -f out.csv.part

# --- successful runs -----------------------------------------------------------------------
echo "precious" > out.csv
if "$VARSYM" run -o out.csv 2> stderr.txt; then ok; else bad "default run failed: $(cat stderr.txt)"; fi
[ "$(head -1 out.csv)" = "step,t,q,p,energy,q_exact,p_exact" ] && ok || bad "header: $(head -1 out.csv)"
[ "$(wc -l < out.csv)" -eq 52 ] && ok || bad "default run: $(wc -l < out.csv) lines, expected 52"
[ "$(tail -1 out.csv | cut -d, -f1)" = "50" ] && ok || bad "last row: $(tail -1 out.csv)"
[ ! -e out.csv.part ] && ok || bad "out.csv.part left after success"
[ ! -s stderr.txt ] && ok || bad "stderr not empty on success: $(cat stderr.txt)"
# 17 significant digits: the initial q is pi/2 printed exactly.
[ "$(sed -n 2p out.csv | cut -d, -f3)" = "1.5707963267948966" ] && ok || bad "q0 row: $(sed -n 2p out.csv)"
# After one period Simpson's q is within 2e-6 of the exact value (Table 1: 1.05e-6 at N = 50).
awk -F, 'END { d = $3 - $6; if (d < 0) d = -d; exit !(d < 2e-6) }' out.csv && ok || bad "final error: $(tail -1 out.csv)"

"$VARSYM" run --every 0 --periods 2 > every0.csv && [ "$(wc -l < every0.csv)" -eq 2 ] &&
  [ "$(tail -1 every0.csv | cut -d, -f1)" = "100" ] && ok || bad "--every 0: $(cat every0.csv)"
"$VARSYM" run --every 7 > every7.csv &&
  [ "$(cut -d, -f1 every7.csv | tail -n +2 | tr '\n' ' ')" = "0 7 14 21 28 35 42 49 50 " ] && ok ||
  bad "--every 7: $(cut -d, -f1 every7.csv | tr '\n' ' ')"
"$VARSYM" run --scheme newmark --time 2 --steps 40 --q0 0.5 --p0 4 --mass 2 --omega 3 > t.csv &&
  [ "$(tail -1 t.csv | cut -d, -f1,2)" = "40,2" ] && ok || bad "--time/--steps: $(tail -1 t.csv)"
"$VARSYM" run --q0 1 --p0 20 --periods 2 > rot.csv && ok || bad "rotation run failed"
"$VARSYM" run --stats > /dev/null 2> stats.txt && grep -q 'Newton iterations per step mean' stats.txt && ok ||
  bad "--stats: $(cat stats.txt)"

"$VARSYM" paper table1 --format csv > t1.csv && [ "$(head -1 t1.csv)" = "scheme,quantity,steps,error" ] &&
  [ "$(wc -l < t1.csv)" -eq 19 ] && grep -q '^simpson,state,200,4.06' t1.csv && ok || bad "table1 csv: $(cat t1.csv)"
"$VARSYM" paper table1 | grep -q 'Symplectic Simpson   relative energy' && ok || bad "table1 text"

# The family: lobatto degree 2 is the Simpson scheme, gauss degree 1 the Newmark scheme.
"$VARSYM" run --every 0 > simpson.csv && "$VARSYM" run --scheme lobatto --degree 2 --every 0 > lob2.csv &&
  paste -d, simpson.csv lob2.csv | awk -F, 'NR == 2 { d = $3 - $10; if (d < 0) d = -d; exit !(d < 1e-13) }' && ok ||
  bad "lobatto 2 vs simpson: $(tail -1 simpson.csv) / $(tail -1 lob2.csv)"
"$VARSYM" run --scheme newmark --every 0 > newmark.csv && "$VARSYM" run --scheme gauss --degree 1 --every 0 > gauss1.csv &&
  paste -d, newmark.csv gauss1.csv | awk -F, 'NR == 2 { d = $3 - $10; if (d < 0) d = -d; exit !(d < 1e-13) }' && ok ||
  bad "gauss 1 vs newmark: $(tail -1 newmark.csv) / $(tail -1 gauss1.csv)"
"$VARSYM" converge --scheme gauss --degree 2 --format csv > conv.csv &&
  [ "$(head -1 conv.csv)" = "scheme,degree,quantity,steps,error" ] && [ "$(wc -l < conv.csv)" -eq 13 ] &&
  grep -q '^gauss,2,momentum,25,' conv.csv && ok || bad "converge csv: $(cat conv.csv)"
# Simpson's rows at 50, 100, 200 steps are Table 1's (state error 1.05e-06 at N = 50).
"$VARSYM" converge --scheme simpson --format csv | grep -q '^simpson,2,state,50,1.0496' && ok || bad "converge simpson state"
"$VARSYM" converge --scheme lobatto --degree 3 --steps 32,64,128 > conv.txt &&
  grep -Eq '^ +fitted +(5\.9|6\.0)' conv.txt && ok || bad "converge fitted order: $(cat conv.txt)"

if command -v gnuplot > /dev/null; then
  "$VARSYM" converge --steps 25,50 --plot conv.png -o conv.txt 2> stderr.txt && [ -s conv.png ] && [ -s conv.gp ] &&
    ok || bad "converge --plot: $(cat stderr.txt)"
  "$VARSYM" paper figure2 -o fig.svg -o fig.png 2> stderr.txt && ok || bad "figure2: $(cat stderr.txt)"
  for f in fig.png fig.svg fig.csv fig-exact.csv fig.gp; do [ -s "$f" ] && ok || bad "figure2 did not write $f"; done
  [ "$(head -c 8 fig.png | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] && ok || bad "fig.png is not a PNG"
  grep -q '<svg' fig.svg && ok || bad "fig.svg is not SVG"
  [ "$(wc -l < fig.csv)" -eq 52 ] && ok || bad "fig.csv: $(wc -l < fig.csv) lines"
  (gnuplot fig.gp) 2> gp.txt && ok || bad "fig.gp does not redraw: $(cat gp.txt)"
  ls ./*.part > /dev/null 2>&1 && bad "figure left .part files" || ok
else
  skip "converge --plot and paper figure2: gnuplot not installed (make test installs it)"
fi

# --- models (issue 3) ----------------------------------------------------------------------
"$VARSYM" models > models.txt && for m in pendulum oscillator kepler double-pendulum heavy-top chain; do
  grep -q "^$m: " models.txt || { bad "varsym models does not list $m"; continue; }; ok; done
grep -q 'angular_momentum' models.txt && grep -q 'p_phi' models.txt && ok || bad "models: conserved quantities"

# Each model runs with its defaults and writes the documented header.
header_of() { "$VARSYM" run --model "$1" --every 0 "${@:2}" 2> stderr.txt | head -1; }
[ "$(header_of kepler)" = "step,t,q_1,q_2,p_1,p_2,energy,angular_momentum,q_1_exact,q_2_exact,p_1_exact,p_2_exact" ] &&
  ok || bad "kepler header: $(header_of kepler) $(cat stderr.txt)"
[ "$(header_of oscillator)" = "step,t,q_1,q_2,p_1,p_2,energy,q_1_exact,q_2_exact,p_1_exact,p_2_exact" ] &&
  ok || bad "oscillator header: $(header_of oscillator) $(cat stderr.txt)"
[ "$(header_of heavy-top)" = "step,t,q_1,q_2,q_3,p_1,p_2,p_3,energy,p_phi,p_psi,q_1_exact" ] &&
  ok || bad "heavy-top header: $(header_of heavy-top) $(cat stderr.txt)"
[ "$(header_of double-pendulum)" = "step,t,q_1,q_2,p_1,p_2,energy" ] && ok || bad "double-pendulum header"
[ "$(header_of chain --n 3)" = "step,t,q_1,q_2,q_3,p_1,p_2,p_3,energy" ] && ok || bad "chain header: $(header_of chain --n 3)"
[ "$(header_of pendulum)" = "step,t,q,p,energy,q_exact,p_exact" ] && ok || bad "pendulum header"

# Kepler, 10 orbits: angular momentum (column 8) constant to 1e-12 relative on every row, and
# the final position within 1e-4 of the exact orbit (Simpson at 200 steps/orbit: ~5e-5).
"$VARSYM" run --model kepler --periods 10 > kep.csv &&
  awk -F, 'NR == 2 { l0 = $8 } NR > 2 { d = ($8 - l0) / l0; if (d < 0) d = -d; if (d > m) m = d }
           END { e = $3 - $9; if (e < 0) e = -e; exit !(m <= 1e-12 && e < 1e-4) }' kep.csv && ok ||
  bad "kepler conservation/accuracy: $(tail -1 kep.csv)"
# Heavy top: p_phi and p_psi (columns 10, 11) identical on every row (cyclic coordinates).
"$VARSYM" run --model heavy-top --periods 3 --scheme gauss --degree 2 > top.csv &&
  [ "$(cut -d, -f10,11 top.csv | tail -n +2 | sort -u | wc -l)" -eq 1 ] && ok || bad "heavy-top momenta vary"
"$VARSYM" run --model oscillator --dim 3 --mass-matrix 1,2,3 --stiffness-matrix 4 --q0 1,0,0 --v0 0,1,0 --every 0 > osc.csv &&
  ok || bad "oscillator with matrices: $(cat stderr.txt)"
"$VARSYM" run --model double-pendulum --masses 1,2 --lengths 1,0.5 --joint-stiffness 2 --time 1 --steps 500 --every 0 > dp.csv &&
  ok || bad "double pendulum with parameters"
# The general engine's simplified iteration (the default with automatic derivatives) takes
# Newton's steps (to round-off: 1e-12 over 500 steps of the chaotic double pendulum; measured
# equal to the last bit).
"$VARSYM" run --model double-pendulum --time 1 --steps 500 --every 0 --scheme gauss --degree 3 \
  > dps.csv &&
  "$VARSYM" run --model double-pendulum --time 1 --steps 500 --every 0 --scheme gauss --degree 3 \
    --iteration newton > dpn.csv &&
  paste -d, <(tail -1 dps.csv) <(tail -1 dpn.csv) |
  awk -F, '{ d = 0; for (i = 3; i <= 7; ++i) { x = $i - $(i + 7); if (x < 0) x = -x; if (x > d) d = x }
             exit !(d <= 1e-12 && NF == 14) }' && ok || bad "double pendulum simplified != newton"

expect_error 2 "another model's option" "--eccentricity is a parameter of --model kepler, not of --model pendulum" run --eccentricity 0.3 -o out.csv
expect_error 2 "eccentricity 1" "--eccentricity: eccentricity must be 0 <= eccentricity < 1" run --model kepler --eccentricity 1 -o out.csv
expect_error 2 "kepler with q0" "kepler: it starts at pericentre: set the orbit with" run --model kepler --q0 1,0 -o out.csv
expect_error 2 "unknown model" "--model: rocket not in" run --model rocket -o out.csv
expect_error 2 "q0 wrong length" "heavy-top: q0 needs 3 values (th, phi, psi), got 2" run --model heavy-top --q0 1,0 -o out.csv
expect_error 2 "period for double pendulum" "--model double-pendulum has no period: give the run's" run --model double-pendulum --periods 2 -o out.csv
expect_error 2 "chain with a dense family member at large n" "chain: lobatto-3 solves a dense system of 3 n unknowns a" run --model chain --scheme lobatto --degree 3 --n 5000 -o out.csv
# The chain on the family (dense Newton): gauss-2 (order 4) at n = 16, h = 0.1 keeps the energy
# (column 35) to 1e-9 relative over 1000 steps against the first row's (measured 4.2e-11;
# Newmark, order 2, gives 1.1e-6 on the same run, so a wrong order would fail).
"$VARSYM" run --model chain --n 16 --scheme gauss --degree 2 > chain.csv &&
  awk -F, 'NR == 2 { e0 = $35 } NR > 2 { d = ($35 - e0) / e0; if (d < 0) d = -d; if (d > m) m = d }
           END { exit !(NR == 1002 && m < 1e-9) }' chain.csv && ok || bad "chain on gauss-2: $(tail -1 chain.csv)"
expect_error 2 "chain n zero" "--n: n must be a whole number, 1 <= n <= 10000000, got 0" run --model chain --n 0 -o out.csv
expect_error 2 "oscillator bad matrix size" "oscillator: mass_matrix needs 1, 3 or 9 values for dim 3" run --model oscillator --dim 3 --mass-matrix 1,2 -o out.csv
expect_error 2 "oscillator indefinite K" "oscillator: stiffness matrix is not positive definite" run --model oscillator --stiffness-matrix 1,-1 -o out.csv
expect_error 2 "double pendulum zero mass" "--masses: m1 must be positive, got 0" run --model double-pendulum --masses 0,1 -o out.csv
expect_error 2 "p0 and v0" "--p0 excludes --v0" run --model heavy-top --p0 0,1,1 --v0 0,1,1 -o out.csv
# A top standing vertically: the Euler angles' mass matrix is singular at theta = 0.
expect_error 2 "singular mass matrix" "heavy-top: the mass matrix d2L/dqdot2 is singular or not" run --model heavy-top --q0 0,0,0 -o out.csv
grep -q 'singular' stderr.txt && ok || bad "singular mass message: $(cat stderr.txt)"
# Ten steps over 100 s of the chaotic double pendulum: Newton cannot converge.
expect_error 3 "double pendulum step too large" "Newton's method did not converge in step 1 (t = 0 -> 10)" run --model double-pendulum --time 100 --steps 10 -o out.csv
grep -q 'step 1 (t = 0' stderr.txt && [ -f out.csv.part ] && [ "$(wc -l < out.csv.part)" -eq 2 ] && ok ||
  bad "divergence message/rows: $(cat stderr.txt)"
rm -f out.csv.part

# --- config files --------------------------------------------------------------------------
cat > kep.toml <<'TOML'
# Kepler orbit, moderate eccentricity
model = "kepler"
eccentricity = 0.3
steps-per-period = 100
periods = 2
every = 50
TOML
"$VARSYM" run --config kep.toml > cfg.csv 2> stderr.txt &&
  "$VARSYM" run --model kepler --eccentricity 0.3 --steps-per-period 100 --periods 2 --every 50 > opt.csv &&
  cmp -s cfg.csv opt.csv && ok || bad "config run differs from the same options: $(cat stderr.txt)"
"$VARSYM" run --config kep.toml --periods 1 > cfg1.csv && [ "$(tail -1 cfg1.csv | cut -d, -f1)" = "100" ] && ok ||
  bad "command line should override the config file"
printf 'model = "kepler"\nq0 = [1.0, 0.0]\nstats = true\n' > list.toml
expect_error 2 "config list for kepler" "kepler: it starts at pericentre: set the orbit with" run --config list.toml -o out.csv
printf 'model = "kepler"\n\neccentricty = 0.3\n' > typo.toml
expect_error 2 "config unknown key" "typo.toml:3: unknown key 'eccentricty'" run --config typo.toml -o out.csv
grep -q 'typo.toml:3: unknown key .eccentricty.' stderr.txt && ok || bad "unknown key message: $(cat stderr.txt)"
printf 'model = "kepler"\neccentricity = "high"\n' > type.toml
expect_error 2 "config wrong type" "type.toml:2: key 'eccentricity' expects a number" run --config type.toml -o out.csv
grep -q "type.toml:2: key 'eccentricity' expects a number" stderr.txt && ok || bad "type message: $(cat stderr.txt)"
printf 'model = "kepler"\nsteps = 2.5\n' > int.toml
expect_error 2 "config float for integer" "int.toml:2: key 'steps' expects a whole number" run --config int.toml -o out.csv
printf 'model = "kepler"\n\n\neccentricity = 1.5\n' > range.toml
expect_error 2 "config out of range" "range.toml:4: key 'eccentricity': --eccentricity" run --config range.toml -o out.csv
grep -q "range.toml:4: key 'eccentricity'" stderr.txt && ok || bad "range message: $(cat stderr.txt)"
printf 'model = "kepler"\nperiods = [1, 2]\n' > scalar.toml
expect_error 2 "config list for a scalar" "scalar.toml:2: key 'periods' takes one value, not a list" run --config scalar.toml -o out.csv
printf 'model = \n' > syntax.toml
expect_error 2 "config syntax error" "syntax.toml:1: Error while parsing key-value pair: expected" run --config syntax.toml -o out.csv
grep -q 'syntax.toml:1' stderr.txt && ok || bad "syntax message: $(cat stderr.txt)"
expect_error 2 "config missing file" "cannot read config file 'nowhere.toml': No such file or" run --config nowhere.toml -o out.csv
# A repeatable option takes a list: plot = ["a.png", "a.svg"] draws both (it was refused).
printf 'model = "pendulum"\ntime = 2\nfrom = [0]\nto = [1]\nplot = ["pic.png", "pic.svg"]\n' > plots.toml
"$VARSYM" optimize --config plots.toml -o plots.csv --quiet 2> stderr.txt && [ -s pic.png ] &&
  [ -s pic.svg ] && ok || bad "config plot list: $(cat stderr.txt)"
printf 'model = "pendulum"\ntime = 2\nfrom = [0]\nto = [1]\nplot = ["pic.png", 3]\n' > plot3.toml
expect_error 2 "config plot list with a number" "plot3.toml:5: key 'plot': every entry expects a string" optimize --config plot3.toml -o out.csv

# --- bench (issue 5): tiny settings; one row per method and N, ratios to odeint's peer ----------
"$VARSYM" bench --problems pendulum --schemes simpson,gauss-2 --compositions none --steps 25,50 \
  --periods 2 --q0 1.5707963267948966 --repetitions 1 --format csv > bench.csv 2> stderr.txt &&
  [ "$(head -1 bench.csv)" = "problem,method,order,steps_per_period,error,max_rel_energy_error,ns_per_step,us_per_period,newton_per_step,peer,ns_ratio,error_ratio" ] &&
  [ "$(wc -l < bench.csv)" -eq 11 ] && grep -q '^pendulum,simpson,4,50,.*,odeint-sb3a_mclachlan,' bench.csv && ok ||
  bad "bench csv: $(cat bench.csv) $(cat stderr.txt)"
# A second amplitude is its own problem; a composition is one more method; the text table ends
# with the cheapest cost at each error level.
"$VARSYM" bench --problems pendulum --schemes gauss-3 --compositions kahan-li-8 --steps 25,50 \
  --periods 2 --q0 2.5 --repetitions 1 > bench.txt 2> stderr.txt &&
  grep -q '^pendulum-2.5 *kahan-li-8 *8 *50 ' bench.txt && grep -q '^Cheapest us per period' bench.txt &&
  [ "$(grep -c '^pendulum-2.5 ' bench.txt)" -eq 15 ] && ok || bad "bench q0, composition: $(cat bench.txt)" # 10 rows, 5 cheapest
# The outer solar system against its long double reference: gauss-4 at h ≈ 108 days (40 steps
# per Jupiter period) over 20 000 days.
"$VARSYM" bench --problems solar --schemes gauss-4 --compositions none --solar-steps 40 --days 20000 \
  --repetitions 1 --format csv > solar.csv 2> stderr.txt &&
  awk -F, '$1 == "solar" && $2 == "gauss-4" { found = 1; exit !($5 < 1e-6) } END { exit !found }' solar.csv &&
  ok || bad "bench solar: $(cat solar.csv) $(cat stderr.txt)"
# The work-precision figure gives every curve its own colour (17 curves once shared gnuplot's 8):
# as many distinct stroke colours in the SVG as methods in the table, plus the grid's.
if command -v gnuplot > /dev/null; then
  "$VARSYM" bench --problems pendulum --schemes newmark,simpson,lobatto-3,lobatto-4,lobatto-5,lobatto-6,gauss-2,gauss-3,gauss-4,gauss-5,gauss-6,gauss-4/fixed-point+forces \
    --compositions yoshida-6,kahan-li-8 --steps 10,20 --periods 1 --repetitions 1 --format csv \
    -o wpc.csv --plot wpc.svg 2> stderr.txt &&
    methods=$(tail -n +2 wpc.csv | cut -d, -f2 | sort -u | wc -l) &&
    colours=$(grep -o "stroke='rgb([0-9, ]*)'" wpc.svg | sort -u | wc -l) &&
    [ "$methods" -ge 16 ] && [ "$colours" -ge $((methods + 1)) ] && ok ||
    bad "bench figure colours: $methods methods, $colours colours $(cat stderr.txt)"
else
  skip "bench --plot: gnuplot not installed (make test installs it)"
fi
expect_error 2 "bench q0 beyond pi" "--q0 must be between 0 and pi rad (exclusive), got 4.000000" bench --q0 4 -o out.csv
expect_error 2 "bench unknown composition" "--compositions: unknown composition 'euler'" bench --compositions euler -o out.csv
expect_error 2 "bench zero days" "--days: must be > 0, got '0'" bench --days 0 -o out.csv
# Simpson's error at N = 50 over 2 periods is Table 1's regime (~1e-6 per period): below 1e-5.
awk -F, '$2 == "simpson" && $4 == 50 { exit !($5 < 1e-5) }' bench.csv && ok || bad "bench simpson error"
expect_error 2 "bench zero repetitions" "--repetitions: must be >= 1, got '0'" bench --repetitions 0 -o out.csv
expect_error 2 "bench unknown problem" "--problems: rocket not in {pendulum,kepler,solar}" bench --problems rocket -o out.csv
expect_error 2 "bench unknown scheme" "unknown scheme 'euler' in --schemes" bench --schemes euler --periods 1 --steps 25 -o out.csv
expect_error 2 "bench zero steps" "--steps: must be >= 1, got '0'" bench --steps 0 -o out.csv

# Determinism: the same command gives byte-identical output (no -ffast-math, no threads, no
# randomness; README "Determinism").
"$VARSYM" run --model double-pendulum --time 5 --steps 2000 > det1.csv &&
  "$VARSYM" run --model double-pendulum --time 5 --steps 2000 > det2.csv && cmp -s det1.csv det2.csv && ok ||
  bad "two identical runs differ"

"$VARSYM" --help | grep -q 'Exit codes' && ok || bad "--help"
"$VARSYM" run --help | grep -q 'step,t,q,p,energy,q_exact,p_exact' && ok || bad "run --help"
"$VARSYM" run --help | grep -Eq -- '--n INT:a whole number' && "$VARSYM" run --help | grep -Eq -- '--omega FLOAT:' && ok ||
  bad "run --help: a count (--n) shows INT, a real parameter (--omega) FLOAT"

finish
