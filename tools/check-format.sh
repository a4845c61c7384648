#!/usr/bin/env bash
# Fails when a C++ file of ours differs from what clang-format (root .clang-format) makes
# of it. `tools/check-format.sh --fix` rewrites them instead.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(find common fem mpm transfer tools tests \
  \( -name '*.cpp' -o -name '*.hpp' \) -not -path '*/data/*' | sort)
if [[ ${1:-} == --fix ]]; then
  clang-format -i "${files[@]}"
else
  clang-format --dry-run --Werror "${files[@]}"
  echo "check-format: ${#files[@]} files formatted"
fi
