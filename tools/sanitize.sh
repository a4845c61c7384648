#!/usr/bin/env bash
# The default test suite (ctest -L 'unit|integration') under AddressSanitizer (with
# LeakSanitizer) and UndefinedBehaviorSanitizer: installs what is missing, configures the
# `sanitize` preset of CMakePresets.json (everything built with
# -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined,
# -O2 -g, in build-sanitize/, the default build/ untouched), builds and runs the suite.
#
#   tools/sanitize.sh [CTEST_ARGS...]      e.g. tools/sanitize.sh -R programs_cli
#
# Any report fails: a memory error, a leak or undefined behaviour ends the program with
# exit status 86 (no program of ours uses it) and a stack on stderr; the CLI tests also
# fail on a report in a program's stderr where they expect a non-zero exit anyway, and
# this script fails if a report shows anywhere in the suite's log. Leaks are checked
# (detect_leaks=1); tools/sanitize.supp lists the reports from libraries that are not
# ours, each with why. The run-time options live in the preset's test environment, so
# `ctest --preset sanitize` alone runs the same; this script only adds a longer default
# timeout (the instrumented programs run 2-5 times slower).
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
