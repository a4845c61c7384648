#!/usr/bin/env bash
# prefer_yielding_threads: without a wait policy in the environment the program starts
# again, once, with OMP_WAIT_POLICY=passive; a policy or spin count the user set is kept and
# the program starts once.
#   wait_setting_test.sh PRINT_WAIT_SETTING
set -euo pipefail
program=$1
expect() {  # WANTED, then the environment to run with
  local wanted=$1 got
  shift
  got=$(env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT -u SLIDE_TEST_STARTS "$@" "$program")
  [[ $got == "$wanted" ]] || { echo "wait_setting_test: with '$*': '$got', wanted '$wanted'" >&2; exit 1; }
}
expect "GOMP_SPINCOUNT=unset OMP_WAIT_POLICY=passive starts=2"
expect "GOMP_SPINCOUNT=unset OMP_WAIT_POLICY=active starts=1" OMP_WAIT_POLICY=active
expect "GOMP_SPINCOUNT=5 OMP_WAIT_POLICY=unset starts=1" GOMP_SPINCOUNT=5
echo "wait_setting_test: passed"
