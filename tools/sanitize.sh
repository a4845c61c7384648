#!/usr/bin/env bash
# The default test suite (ctest -L 'unit|integration') under AddressSanitizer (with
# LeakSanitizer) and UndefinedBehaviorSanitizer: installs what is missing, configures the
# `sanitize` preset of CMakePresets.json (everything built with
# -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined,
# RelWithDebInfo = -O2 -g, in build-sanitize/; the default build/ is untouched), builds,
# and runs the suite there.
#
#   tools/sanitize.sh [CTEST_ARGS...]      e.g. tools/sanitize.sh -R programs_cli
#   SANITIZE_TIMEOUT=5000 tools/sanitize.sh   ctest's limit per test (default 3000 s)
#
# Any report fails a test: a memory error, a leak or undefined behaviour ends the program
# with exit status 86 (ASAN_OPTIONS/LSAN_OPTIONS/UBSAN_OPTIONS exitcode=86, halt_on_error,
# print_stacktrace; no program of ours exits with 86) and its stack on stderr. The CLI
# tests also fail on a report in a program's stderr where they expect a non-zero exit
# anyway (tests/support/programs.hpp, tests/common/programs_cli.sh), the test
# sanitize.canary checks that deliberate bugs are caught this way, and this script fails
# if a report shows anywhere in the suite's log. Leaks are checked (detect_leaks=1);
# tools/sanitize.supp lists the leaks of libraries that are not ours, each with why.
#
# The run-time options live in the preset's test environment, so `ctest --preset
# sanitize` alone runs the same; OMP_WAIT_POLICY=passive there keeps OpenMP's barriers
# from spinning against the other jobs of a shared machine (the results do not depend on
# the thread count). The instrumented programs run 10-20 times slower than the Release
# build: the preset multiplies the tests' own TIMEOUTs by 10 (SLIDE_TEST_TIMEOUT_FACTOR;
# ctest's --timeout cannot raise those) and this script gives the others 3000 s each.
# detect_stack_use_after_return stays off: it made fem-solve another 1.5 times slower.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install-deps.sh

seconds() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(seconds)" 'BEGIN { printf "%.0f s", b - a }'; }

start=$(seconds)
cmake --preset sanitize > /dev/null
cmake --build --preset sanitize
echo "sanitize: build $(elapsed "$start")"

start=$(seconds)
status=0
ctest --preset sanitize --timeout "${SANITIZE_TIMEOUT:-3000}" "$@" || status=$?
echo "sanitize: suite $(elapsed "$start")"

# A report that a test let pass (its program was expected to fail and its stderr was not
# checked) would still be in the log of every test's output.
log=build-sanitize/Testing/Temporary/LastTest.log
if grep -nE '==[0-9]+==ERROR: (Address|Leak)Sanitizer|^[^ ]+: runtime error: ' "$log"; then
  echo "sanitize: sanitizer reports in $log (above)" >&2
  status=1
fi
exit $status
