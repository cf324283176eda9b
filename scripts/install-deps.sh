#!/usr/bin/env bash
# Installs the Debian packages varsym needs to build, test and plot (and those named as
# arguments). Idempotent: silent when
# everything is present; otherwise one apt-get run (as root, or through sudo when available).
set -euo pipefail

packages=(
  cmake make g++ clang      # toolchain (make builds with clang++: it compiles twice as fast)
  libeigen3-dev             # linear algebra
  libboost-dev              # Boost.Math (elliptic functions, quadrature), Boost.Odeint
  libcli11-dev              # command line
  libtomlplusplus-dev       # config files (varsym run --config)
  libtinyxml2-dev           # URDF robots (varsym run --urdf)
  libgtest-dev              # tests
  libbenchmark-dev          # benchmarks
  gnuplot-nox               # figures (pngcairo and svg terminals)
  libopenmpi-dev openmpi-bin # mpirun varsym ensemble (optional: the tool builds without)
  coinor-libipopt-dev pkg-config # IPOPT, the NLP solver of varsym optimize (found by pkg-config)
  libopenblas0-serial       # OpenBLAS for IPOPT's MUMPS: the system's BLAS and LAPACK (below)
  python3-dev pybind11-dev  # the Python package (make python)
  python3-numpy python3-pytest python3-sympy python3-matplotlib # its tests and examples
  python3-tqdm                                                  # its progress bars
  python3-pip python3-setuptools python3-wheel python3-venv     # pip install . (docs/python.md)
  libjs-three               # three.js, inlined into --animate's pages (docs/robots.md)
  chromium                  # headless: the animation pages' browser tests, --snapshot
)
packages+=("$@")            # more for one target: make fuzz adds clang and libclang-rt-14-dev

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "varsym: installing missing Debian packages: ${missing[*]}" >&2
for p in "${missing[@]}"; do
  if [ "$p" = libopenblas0-serial ]; then
    triplet=$(gcc -print-multiarch 2>/dev/null || echo x86_64-linux-gnu)
    echo "varsym: libopenblas0-serial becomes the system's libblas.so.3 and liblapack.so.3 for" \
      "every program (Debian's alternatives; IPOPT's optimal control of robots of 10 links and" \
      "more iterates 1.3-1.6 times faster); to go back:" \
      "update-alternatives --config libblas.so.3-$triplet (and liblapack.so.3-$triplet)" >&2
  fi
done
sudo=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then sudo=(sudo); else
    echo "varsym: need root to install ${missing[*]}; run: apt-get install ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# apt's own chatter goes to a log, shown only if something fails.
if ! { "${sudo[@]}" apt-get update -qq && "${sudo[@]}" apt-get install -y -qq "${missing[@]}"; } >"$log" 2>&1; then
  cat "$log" >&2
  echo "varsym: could not install ${missing[*]} (see the apt output above)" >&2
  exit 1
fi
