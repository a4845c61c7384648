#!/usr/bin/env bash
# The README's second command: install what is missing, configure, build, run the whole
# default test suite (unit + integration, < 15 minutes on 2 cores). CI runs exactly this,
# then tools/test-mpi.sh. When an MPI build exists (build-mpi/, see docs/parallel.md), its
# tests run too, on 2 and 3 ranks.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
ctest --test-dir build --output-on-failure --label-regex 'unit|integration' \
  --parallel "$(nproc)" --timeout 900

if [[ -f build-mpi/CMakeCache.txt ]]; then tools/test-mpi.sh; fi
