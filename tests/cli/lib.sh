# tests/cli/lib.sh: what the command-line test scripts share (sourced with VARSYM's path as $1):
# a scratch directory removed at exit, pass/fail counting and expect_error.
set -u
VARSYM=$(realpath "${1:?usage: ${0##*/} PATH_TO_VARSYM}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
passed=0

ok() { passed=$((passed + 1)); }
bad() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_error CODE NAME ARGS...: exit status CODE, exactly one line on stderr starting with
# "varsym: error:", nothing named out.csv created, and a pre-existing keep.csv unchanged.
expect_error() {
  local code=$1 name=$2
  shift 2
  rm -f out.csv out.csv.part
  echo "precious" > keep.csv
  "$VARSYM" "$@" > stdout.txt 2> stderr.txt
  local rc=$?
  local lines
  lines=$(wc -l < stderr.txt)
  if [ "$rc" -ne "$code" ]; then bad "$name: exit $rc, expected $code ($(cat stderr.txt))"; return; fi
  if [ "$lines" -ne 1 ]; then bad "$name: $lines lines on stderr: $(cat stderr.txt)"; return; fi
  if ! grep -q '^varsym: error: ' stderr.txt; then bad "$name: message: $(cat stderr.txt)"; return; fi
  if [ -e out.csv ]; then bad "$name: left out.csv behind"; return; fi
  if [ "$(cat keep.csv)" != "precious" ]; then bad "$name: changed keep.csv"; return; fi
  ok
}


# finish: the summary line; the script's status is whether every check passed.
finish() {
  echo "$passed passed, $failures failed"
  [ "$failures" -eq 0 ]
}
