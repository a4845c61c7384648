#!/usr/bin/env bash
# The README's second command: install what is missing, configure, build, run the whole
# default test suite (unit + integration, < 15 minutes on 2 cores). CI runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
ctest --test-dir build --output-on-failure --label-regex 'unit|integration' \
  --parallel "$(nproc)" --timeout 900
