#!/usr/bin/env bash
# bench/ensemble_throughput.sh VARSYM [SIDE]: throughput of `varsym ensemble` in members/s on this
# machine: a SIDE × SIDE grid (default 1000: 10⁶ members) of pendulums, 1000 Simpson steps each
# with the tangent map (λ and MEGNO), on 1 and 2 threads, then through mpirun on 1, 2 and 4 ranks
# of one thread each (where varsym is built with MPI): the MPI overhead is the time against the
# same number of threads in one process. Every output is compared with the first (cmp).
set -euo pipefail
VARSYM=$(realpath "${1:?usage: ${0##*/} PATH_TO_VARSYM [SIDE]}")
side=${2:-1000}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
args=(ensemble --model pendulum --grid q0_1=-3:3:$side --grid p0_1=-6:6:$side --time 10 --steps 1000)
members=$((side * side))
run() { # label, command...: prints the line of one run
  local label=$1 out=$2
  shift 2
  local t0 t1
  t0=$(date +%s.%N)
  "$@" -o "$out" 2> /dev/null
  t1=$(date +%s.%N)
  local s
  s=$(echo "$t1 - $t0" | bc -l)
  printf '%-26s %8.2f s %12.0f members/s %s\n' "$label" "$s" "$(echo "$members / $s" | bc -l)" \
    "$(cmp -s "$out" threads1.csv && echo '(same file)' || echo '')"
}
echo "$members members × 1000 steps (pendulum, simpson, tangent map on), $(nproc) cores"
run "1 thread" threads1.csv "$VARSYM" "${args[@]}" --threads 1
run "2 threads" threads2.csv "$VARSYM" "${args[@]}" --threads 2
if ldd "$VARSYM" | grep -q libmpi && command -v mpirun > /dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  for n in 1 2 4; do
    run "mpirun -np $n, 1 thread each" mpi$n.csv mpirun -np $n "$VARSYM" "${args[@]}" --threads 1
  done
else
  echo "MPI: not built in (VARSYM_MPI) or no mpirun"
fi
