#!/usr/bin/env bash
# One run per output folder (common/run/output_lock.hpp), through the programs: a run into
# a folder a live run holds is refused with one line naming it and writes nothing; the
# lock a killed run left is taken over; a finished run leaves no lock.
#
#   lock_test.sh SOURCE_DIR BIN SCRATCH
set -uo pipefail
src=$1
bin=$2
scratch=$3
rm -rf "$scratch" && mkdir -p "$scratch/out"
case_file=$src/cases/geostatic-4x4/case.toml
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# A live "run": a process of ours whose mark is in the lock.
sleep 60 &
holder=$!
trap 'kill $holder 2>/dev/null' EXIT
start=$(sed 's/.*) //' "/proc/$holder/stat" | cut -d' ' -f20)
echo "$holder $start $(hostname)" > "$scratch/out/.slide-lock"
"$bin/fem-solve" "$case_file" -o "$scratch/out" -q 2> "$scratch/err"
status=$?
[[ $status -eq 1 ]] || fail "a run into a locked folder: status $status"
[[ $(wc -l < "$scratch/err") -eq 1 ]] || fail "not one line: $(cat "$scratch/err")"
grep -q "another run (pid $holder" "$scratch/err" || fail "the holder is not named: $(cat "$scratch/err")"
[[ $(ls -A "$scratch/out") == .slide-lock ]] || fail "files written: $(ls -A "$scratch/out")"

# The holder is killed: its lock is stale, the next run takes it over, then releases it.
kill -9 $holder
wait $holder 2>/dev/null
"$bin/fem-solve" "$case_file" -o "$scratch/out" > "$scratch/err" 2>&1 ||
  fail "the run after the holder died: $(cat "$scratch/err")"
grep -q "took over the output lock" "$scratch/err" || fail "no word of the lock taken over"
[[ -f $scratch/out/fem_t0.000.h5 ]] || fail "no checkpoint"
[[ ! -e $scratch/out/.slide-lock ]] || fail "a finished run left its lock"

if ((failures > 0)); then echo "$failures failure(s)"; exit 1; fi
echo "lock_test: a locked folder refused in one line, a killed run's lock taken over"
