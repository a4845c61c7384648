#!/usr/bin/env bash
# The sanitize build's own check (tests/sanitize/CMakeLists.txt): each deliberate bug of
# sanitizer_canary must end it with exit status 86 and a sanitizer report on stderr, and
# a run without a bug must exit 0 with nothing on stderr. It fails when the run-time
# options of the sanitize preset (CMakePresets.json) are missing or a report would no
# longer fail a test.
#
#   tests/sanitize/canary_test.sh CANARY_PROGRAM
set -uo pipefail
canary=$1
err=$(mktemp)
trap 'rm -f "$err"' EXIT
failures=0

"$canary" none > /dev/null 2> "$err"
status=$?
if ((status != 0)) || [[ -s $err ]]; then
  echo "FAIL: none: exit status $status, stderr: $(cat "$err")"
  failures=$((failures + 1))
fi

for bug in heap-overflow use-after-free signed-overflow leak; do
  "$canary" "$bug" > /dev/null 2> "$err"
  status=$?
  if ((status != 86)); then
    echo "FAIL: $bug: exit status $status, expected 86"
    failures=$((failures + 1))
  elif ! grep -qE '==[0-9]+==ERROR: (Address|Leak)Sanitizer|: runtime error: ' "$err"; then
    echo "FAIL: $bug: no sanitizer report on stderr: $(cat "$err")"
    failures=$((failures + 1))
  else
    echo "$bug: reported, exit status 86"
  fi
done

((failures == 0)) || { echo "$failures failure(s)"; exit 1; }
echo "canary_test: every deliberate bug was reported with exit status 86"
