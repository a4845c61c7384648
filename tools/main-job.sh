#!/usr/bin/env bash
# The README's first command: install what is missing, configure, build, then run the
# main job: the column-short case end to end (FE to 8 s, transfer at t_T = 2 s ≈ τc and
# at t_T = 0 as the reference, MPM to 20 s, pure MPM, pure FE), its report and plots.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
# Only what the pipeline runs (the test suite and benchmarks build with tools/test.sh).
cmake --build build --target fem-solve fem2mpm mpm-solve slide-metrics

start=$(date +%s)
# Independent runs go in parallel, one OpenMP thread each, one run per core.
make -C cases/column-short main -j"$(nproc)" THREADS=1
echo "main job: column-short finished in $(($(date +%s) - start)) s"
echo "main job: report at cases/column-short/out/report/report.md"
