#!/usr/bin/env bash
# tests/package/package_test.sh MODE SOURCE WORK CXX: builds tests/package/consumer against
# varsym. MODE install: `cmake --install` of a fresh configure of SOURCE into WORK/prefix, then
# the consumer with find_package(varsym CONFIG REQUIRED) and CMAKE_PREFIX_PATH=WORK/prefix.
# MODE subdirectory: the consumer embeds SOURCE with add_subdirectory. Runs the consumer, which
# prints OK. Only the library is configured: no models, tool, tests or benchmarks are built.
# MODE models: `cmake --install` of the built tree BUILD, then a consumer of varsym::models.
# The consumers are compiled with the tests' flags, VARSYM_TEST_FLAGS from the environment (CTest
# sets it from the CMake option of that name).
set -euo pipefail
mode=$1 src=$2 work=$3 cxx=$4 # $5: BUILD, for mode models
rm -rf "$work"
mkdir -p "$work"
quiet() { "$@" >"$work/log.txt" 2>&1 || { cat "$work/log.txt"; echo "FAILED: $*"; exit 1; }; }
consumer=$src/tests/package/consumer
case $mode in
install)
  quiet cmake -S "$src" -B "$work/varsym" -DCMAKE_CXX_COMPILER="$cxx" -DVARSYM_BUILD_TOOL=OFF \
    -DVARSYM_BUILD_MODELS=OFF -DVARSYM_BUILD_OPTIMAL=OFF -DVARSYM_BUILD_TESTS=OFF \
    -DVARSYM_BUILD_BENCH=OFF \
    -DVARSYM_BUILD_EXAMPLES=OFF -Wno-dev
  quiet cmake --install "$work/varsym" --prefix "$work/prefix"
  for f in include/varsym/varsym.hpp include/varsym/version.hpp include/varsym/problems.hpp \
    share/cmake/varsym/varsym-config.cmake share/cmake/varsym/varsym-config-version.cmake; do
    [ -f "$work/prefix/$f" ] || { echo "FAILED: $f not installed"; exit 1; }
  done
  quiet cmake -S "$consumer" -B "$work/consumer" -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_PREFIX_PATH="$work/prefix" -DVARSYM_CONSUME=package \
    -DCMAKE_CXX_FLAGS="${VARSYM_TEST_FLAGS-}"
  ;;
models)
  # The build tree given as SOURCE's sibling BUILD (already built by make test) installed, and a
  # consumer of varsym::models, which prints OK itself.
  quiet cmake --install "$5" --prefix "$work/prefix"
  [ -f "$work/prefix/lib/libvarsym_models.a" ] || [ -f "$work/prefix/lib64/libvarsym_models.a" ] ||
    [ -n "$(find "$work/prefix" -name libvarsym_models.a)" ] ||
    { echo "FAILED: libvarsym_models.a not installed"; exit 1; }
  quiet cmake -S "$src/tests/package/models_consumer" -B "$work/consumer" \
    -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$work/prefix"
  quiet cmake --build "$work/consumer"
  "$work/consumer/models_consumer"
  exit 0
  ;;
subdirectory)
  quiet cmake -S "$consumer" -B "$work/consumer" -DCMAKE_CXX_COMPILER="$cxx" \
    -DVARSYM_CONSUME=subdirectory -DVARSYM_SOURCE_DIR="$src" \
    -DCMAKE_CXX_FLAGS="${VARSYM_TEST_FLAGS-}"
  ;;
*) echo "usage: package_test.sh install|subdirectory|models SOURCE WORK CXX [BUILD]"; exit 2 ;;
esac
quiet cmake --build "$work/consumer"
"$work/consumer/consumer"
