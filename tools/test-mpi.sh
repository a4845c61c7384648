#!/usr/bin/env bash
# The MPI build's tests (label mpi, tests/mpi/README.md): installs OpenMPI and the
# parallel HDF5 when missing, configures build-mpi/ (-DSLIDE_MPI=ON), builds what the
# tests run and runs them on 2 and 3 ranks (about 2 minutes on 2 cores). tools/test.sh
# calls this when build-mpi/ exists; CI runs both.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh --mpi
cmake -S . -B build-mpi -G Ninja -DCMAKE_BUILD_TYPE=Release -DSLIDE_MPI=ON
cmake --build build-mpi --target mpi-tests  # what the tests run (tests/mpi/CMakeLists.txt)
# (tests/mpi/CMakeLists.txt gives each test the environment OpenMPI needs as root and
# with more ranks than cores.)
ctest --test-dir build-mpi --output-on-failure --label-regex '^mpi$' --timeout 900
