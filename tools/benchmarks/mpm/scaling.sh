#!/usr/bin/env bash
# Scaling of mpm-solve's step loop from 1 to 2 ranks (docs/parallel.md, "Scaling"), with
# bench_mpm of the MPI build on column-short (32 000 particles), one thread per rank:
#   strong: the same column on 1 and on 2 ranks: speedup and parallel efficiency;
#   weak:   the column widened ×2 (64 000 particles) on 2 ranks against 1 rank's column:
#           efficiency = wall per step on 1 rank / wall per step on 2;
#   and, for the same two cores, 1 rank of 2 OpenMP threads.
# Per rank it prints the bytes sent and the exchange time per step.
#
#   tools/benchmarks/mpm/scaling.sh [BUILD_DIR (default build-mpi)] [bench_mpm options]
set -euo pipefail
cd "$(dirname "$0")/../../.."
build=${1:-build-mpi}
shift || true
bench=$build/tools/benchmarks/mpm/bench_mpm
[[ -x $bench ]] || { echo "scaling: no $bench: cmake --build $build --target bench_mpm" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
options=(--repeat 3 --steps 400 --skip 200 "$@")

run() { echo "\$ mpirun $*" >&2; mpirun "$@" | tee /dev/stderr; }
field() { sed -n "s/.*$1=\([0-9.e+-]*\).*/\1/p" <<< "$2" | head -1; }

one=$(run -np 1 "$bench" --threads 1 "${options[@]}")
two=$(run -np 2 "$bench" --threads 1 "${options[@]}")
weak=$(run -np 2 "$bench" --threads 1 --widen 2 "${options[@]}")
threads=$(run -np 1 --bind-to none "$bench" --threads 2 "${options[@]}")

awk -v r1="$(field particle_steps_per_s "$one")" -v r2="$(field particle_steps_per_s "$two")" \
    -v w1="$(field wall_per_step_ms "$one")" -v w2="$(field wall_per_step_ms "$weak")" \
    -v t2="$(field particle_steps_per_s "$threads")" 'BEGIN {
  printf "strong 1 -> 2 ranks: speedup %.2f, parallel efficiency %.0f %%\n", r2 / r1, 50 * r2 / r1
  printf "weak 1 -> 2 ranks (x2 particles): wall per step %.3g -> %.3g ms, efficiency %.0f %%\n",
         w1, w2, 100 * w1 / w2
  printf "same 2 cores as 1 rank x 2 threads: speedup %.2f (2 ranks / 2 threads: %.2f)\n",
         t2 / r1, r2 / t2
}'
