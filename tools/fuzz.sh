#!/usr/bin/env bash
# Fuzzes the seven input readers with libFuzzer (tests/fuzz/README.md): installs what is
# missing (the project's Debian packages, clang 16, the fuzzer runtime, llvm-symbolizer),
# configures build-fuzz/ with clang and -DSLIDE_FUZZ=ON (ASan, UBSan), builds the drivers
# and the three programs (they write the checkpoint seeds), and runs each reader for
# SECONDS_PER_READER (default 120) with its seeds:
#
#   tools/fuzz.sh                      # 2 min per reader
#   tools/fuzz.sh 600                  # 10 min per reader
#   tools/fuzz.sh 600 mpm_checkpoint   # 10 min of one reader (or of several, named)
#
# Prints executions, executions/s, findings and corpus size per reader; the inputs of
# findings and their symbolised reports are in build-fuzz/fuzz/crashes-<reader>/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-120}
[[ $seconds =~ ^[0-9]+$ ]] || { echo "usage: tools/fuzz.sh [SECONDS_PER_READER [READER...]]" >&2; exit 2; }
shift $(($# > 0 ? 1 : 0))
# The target `fuzz` runs tests/fuzz/run_libfuzzer.sh, which reads the readers from here.
export SLIDE_FUZZ_READERS="$*"

tools/install-deps.sh
# Debian 12's clang 16 (clang 14 cannot compile the project: it does not capture structured
# bindings in lambdas, a C++20 feature common/io/checkpoint.cpp uses) with libFuzzer's
# runtime (libclang_rt.fuzzer-x86_64.a is in libclang-rt-16-dev), clang's OpenMP, and
# llvm-symbolizer (in llvm-16) for readable stacks.
packages=(clang-16 libclang-rt-16-dev libomp-16-dev llvm-16)
missing=()
for p in "${packages[@]}"; do
  [[ $(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true) == "install ok installed" ]] || missing+=("$p")
done
if ((${#missing[@]} > 0)); then
  echo "fuzz: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" > /dev/null
fi
export PATH="/usr/lib/llvm-16/bin:$PATH"

mkdir -p build-fuzz
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang-16 -DCMAKE_CXX_COMPILER=clang++-16 \
  -DSLIDE_FUZZ=ON -DSLIDE_BUILD_TESTS=OFF -DSLIDE_BUILD_BENCHMARKS=OFF \
  -DSLIDE_FUZZ_SECONDS="$seconds" > build-fuzz/configure.log 2>&1 ||
  { cat build-fuzz/configure.log >&2; exit 1; }
cmake --build build-fuzz -j2 --target fuzz
