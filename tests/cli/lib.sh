# tests/cli/lib.sh: what the command-line test scripts share (sourced with VARSYM's path as $1):
# a scratch directory removed at exit, pass/fail counting, expect_error, the numeric comparisons
# (each refuses an empty or non-numeric value as a failure of its own, so that a missing field
# or a failed run cannot pass, not even a negated check) and visible skips (exit 77, which CTest
# reports as skipped through SKIP_RETURN_CODE).
set -u
VARSYM=$(realpath "${1:?usage: ${0##*/} PATH_TO_VARSYM}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
passed=0
skipped=()

ok() { passed=$((passed + 1)); }
bad() { echo "FAIL: $*"; failures=$((failures + 1)); }
# skip REASON: a part of the script that could not run; the script then exits 77 (skipped)
# unless something failed.
skip() { echo "SKIP: $*"; skipped+=("$*"); }

# is_number X: X is a decimal number (what awk would read as one, with nothing left over).
is_number() { [[ $1 =~ ^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$ ]]; }
# numbers WHO X...: every X is a number; else a failure naming WHO and the caller's line, and
# status 2. The comparisons below call it first: whether negated or not, an empty value fails.
numbers() {
  local who=$1 x
  shift
  for x in "$@"; do
    is_number "$x" && continue
    bad "$who at line ${BASH_LINENO[1]}: '$x' is not a number (a missing value or a failed run)"
    return 2
  done
}
# near A B TOL: |A - B| <= TOL.
near() {
  numbers near "$@" || return 2
  awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'
}
# rel A B TOL: |A - B| <= TOL |B|.
rel() {
  numbers rel "$@" || return 2
  awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; m = b < 0 ? -b : b
    exit !(d <= t * m) }'
}
# lt A B: A < B; le A B: A <= B; between LO X HI: LO < X < HI.
lt() { numbers lt "$@" || return 2; awk -v a="$1" -v b="$2" 'BEGIN { exit !(a < b) }'; }
le() { numbers le "$@" || return 2; awk -v a="$1" -v b="$2" 'BEGIN { exit !(a <= b) }'; }
between() {
  numbers between "$@" || return 2
  awk -v l="$1" -v x="$2" -v h="$3" 'BEGIN { exit !(l < x && x < h) }'
}

# expect_error CODE NAME WORDS ARGS...: exit status CODE, exactly one line on stderr starting with
# "varsym: error:" and containing WORDS (a fixed string: the words that say what was refused),
# nothing named out.csv created, and a pre-existing keep.csv unchanged. An empty WORDS is refused.
expect_error() {
  local code=$1 name=$2 words=$3
  shift 3
  if [ -z "$words" ]; then bad "$name: expect_error without the words of the message"; return; fi
  rm -f out.csv out.csv.part
  echo "precious" > keep.csv
  "$VARSYM" "$@" > stdout.txt 2> stderr.txt
  local rc=$?
  local lines
  lines=$(wc -l < stderr.txt)
  if [ "$rc" -ne "$code" ]; then bad "$name: exit $rc, expected $code ($(cat stderr.txt))"; return; fi
  if [ "$lines" -ne 1 ]; then bad "$name: $lines lines on stderr: $(cat stderr.txt)"; return; fi
  if ! grep -q '^varsym: error: ' stderr.txt; then bad "$name: message: $(cat stderr.txt)"; return; fi
  if ! grep -qF -- "$words" stderr.txt; then
    bad "$name: the message does not say '$words': $(cat stderr.txt)"
    return
  fi
  if [ -e out.csv ]; then bad "$name: left out.csv behind"; return; fi
  if [ "$(cat keep.csv)" != "precious" ]; then bad "$name: changed keep.csv"; return; fi
  ok
}

# The checkpoint's modification time to the nanosecond, or "none" while there is none.
stamp() { stat -c %.9Y "$1" 2> /dev/null || echo none; }

# kill_and_resume NAME CKPT CSV ARGS...: runs `VARSYM ARGS` (which writes CSV with checkpoint
# CKPT) once straight in ./straight and once in ./killed, killed with SIGKILL every 0.2 s and
# resumed from CKPT until it ends (at most 60 times); checks that both CSVs are byte-identical
# and (not vacuous) that the run was killed at least once. Under the sanitizers, whose runs are
# 10-30 times slower, each kill waits first for a new checkpoint (at most 60 s; 300 kills at
# most): a fixed interval is not enough there (in 0.2 s, and with other builds running in 2 s,
# a sanitized tumbling-body run did not reach its first checkpoint, so restarts made no progress).
kill_and_resume() {
  local name=$1 ckpt=$2 csv=$3 attempts=60 sanitized=${VARSYM_SANITIZED:-}
  [ -n "$sanitized" ] && attempts=300
  shift 3
  mkdir -p straight killed
  (cd straight && "$VARSYM" "$@" 2> err.txt) || bad "uninterrupted $name: $(cat straight/err.txt)"
  (
    cd killed || exit 1
    rc=1
    for attempt in $(seq 1 "$attempts"); do
      if [ -e "$ckpt" ]; then "$VARSYM" run --resume "$ckpt" 2>> err.txt &
      else rm -f "$csv.part"; "$VARSYM" "$@" 2>> err.txt & fi
      pid=$!
      if [ -n "$sanitized" ]; then # until the checkpoint changes, or the run ends
        before=$(stamp "$ckpt")
        for _ in $(seq 600); do
          [ -n "$(ps -o stat= -p "$pid" | grep -v Z)" ] || break
          [ "$(stamp "$ckpt")" = "$before" ] || break
          sleep 0.1
        done
      fi
      sleep 0.2
      kill -9 "$pid" 2> /dev/null
      { wait "$pid"; } 2> /dev/null
      rc=$?
      [ "$rc" -eq 137 ] || break
      echo killed >> kills.txt
    done
    [ "$rc" -eq 137 ] && echo "not finished after $attempts kills" >> err.txt
    exit "$rc"
  ) && cmp -s "straight/$csv" "killed/$csv" && ok ||
    bad "killed and resumed $name differs from the straight run: $(cat killed/err.txt)"
  [ -s killed/kills.txt ] && ok || bad "the $name run was never killed: it ended within 0.2 s"
}

# finish: the summary line; the script's status is whether every check passed, or 77 (skipped)
# when every check that ran passed but a part could not run.
finish() {
  echo "$passed passed, $failures failed, ${#skipped[@]} skipped"
  [ "$failures" -eq 0 ] || exit 1
  [ "${#skipped[@]}" -eq 0 ] || exit 77
}
