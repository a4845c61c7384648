#!/usr/bin/env bash
# An error on any rank ends every rank with one line (fail_on_ranks.cpp): when all ranks
# fail, the root's line alone and status 1; when one fails while its peers wait for it,
# its line with its rank and a non-zero status, within the 3 s grace period plus startup
# (a hang would run into the test's timeout).
# Usage: failure_test.sh FAIL_ON_RANKS MPIEXEC
set -uo pipefail
program=$1 mpiexec=$2
status=0

"$mpiexec" -q -n 3 "$program" all 2> all.err
code=$?
ours=$(grep -c '^fail_on_ranks:' all.err)
if [[ $code -ne 1 || $ours -ne 1 ]] || ! grep -qx "fail_on_ranks: error: every rank's failure" all.err; then
  echo "all ranks failing: status $code, $ours lines of ours:" >&2; cat all.err >&2; status=1
else
  echo "all ranks failing: status 1, one line: $(grep '^fail_on_ranks:' all.err)"
fi

start=$(date +%s)
"$mpiexec" -q -n 3 "$program" one 2> one.err
code=$?
seconds=$(($(date +%s) - start))
ours=$(grep -c '^fail_on_ranks:' one.err)
if [[ $code -eq 0 || $ours -ne 1 ]] || ! grep -qx "fail_on_ranks: error: rank 1: rank 1's own failure" one.err; then
  echo "one rank failing: status $code, $ours lines of ours:" >&2; cat one.err >&2; status=1
else
  echo "one rank failing: status $code after ${seconds} s, our line: $(grep '^fail_on_ranks:' one.err)"
fi

# A failure inside a library's collective (parallel HDF5 on a full disk): rank 1 ends
# every rank after its grace period, with its line, and removes the temporary.
rm -f library.tmp
start=$(date +%s)
"$mpiexec" -q -n 2 "$program" library "$PWD/library.tmp" 2> library.err
code=$?
seconds=$(($(date +%s) - start))
ours=$(grep -c '^fail_on_ranks:' library.err)
if [[ $code -eq 0 || $ours -ne 1 || -e library.tmp ]] ||
  ! grep -qx "fail_on_ranks: error: rank 1: the library's call failed" library.err; then
  echo "a failure inside a library's collective: status $code, $ours lines of ours," \
    "temporary $([[ -e library.tmp ]] && echo left || echo removed):" >&2
  cat library.err >&2; status=1
else
  echo "a failure inside a library's collective: status $code after ${seconds} s," \
    "the temporary removed, our line: $(grep '^fail_on_ranks:' library.err)"
fi
exit $status
