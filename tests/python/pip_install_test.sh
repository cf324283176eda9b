#!/usr/bin/env bash
# The documented offline install (docs/python.md): a venv made from Debian's python3 with its
# packages, `pip install --no-build-isolation --no-index SOURCE`, then varsym imported from
# elsewhere must be the installed copy and compute Table 1. The extension is taken from the
# test build (VARSYM_BUILD_DIR), so the test does not compile it a second time.
# Usage: pip_install_test.sh SOURCE_DIR BUILD_DIR WORK_DIR PYTHON
set -euo pipefail
src=$1 build=$2 work=$3 python=$4
rm -rf "$work"
mkdir -p "$work"
"$python" -m venv --system-site-packages "$work/venv"
VARSYM_BUILD_DIR="$build" "$work/venv/bin/pip" install --quiet --no-build-isolation --no-index \
  --disable-pip-version-check "$src" > "$work/pip.log" 2>&1 || { cat "$work/pip.log"; exit 1; }
cd "$work"
"$work/venv/bin/python" - "$work/venv" <<'PY'
import sys
import varsym

assert varsym.__file__.startswith(sys.argv[1]), varsym.__file__  # the installed copy
table = varsym.table1()
assert len(table) == 18, table
print("installed at", varsym.__file__)
PY
rm -rf "$src/python/varsym.egg-info"
echo OK
