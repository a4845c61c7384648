#!/usr/bin/env bash
# docs/contract.md, "Exit status": every program exits 1 for a missing input file (bad
# input, one line "PROGRAM: error: ...") and 2 for a usage error (an unknown option).
#
#   exit_status_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1 source=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
failures=0
expect() {  # STATUS DESCRIPTION COMMAND...
  local want=$1 what=$2
  shift 2
  "$@" > out.txt 2> err.txt
  local got=$?
  if [[ $got != "$want" ]]; then
    echo "exit_status_test: $what: status $got, expected $want ($(head -c 200 err.txt))"
    failures=$((failures + 1))
  elif [[ $want != 0 && $(wc -l < err.txt) -lt 1 ]]; then
    echo "exit_status_test: $what: no error line"
    failures=$((failures + 1))
  fi
}
case=$source/cases/geostatic-4x4/case.toml
expect 1 "fem-solve, missing case" "$bin/fem-solve" missing.toml -o out
expect 1 "fem2mpm, missing checkpoint" "$bin/fem2mpm" missing.h5 -o p.h5
expect 1 "mpm-solve, missing case" "$bin/mpm-solve" missing.toml -o out
expect 1 "mpm-solve, missing particle file" "$bin/mpm-solve" "$case" -o out --particles missing.h5
expect 1 "slide-metrics measure, missing case" "$bin/slide-metrics" measure missing.toml p.h5
expect 1 "slide-metrics measure, missing particles" "$bin/slide-metrics" measure "$case" missing.h5
expect 1 "slide-metrics transfer-times, missing history" "$bin/slide-metrics" transfer-times "$case" missing.csv
expect 1 "opensees2fem, missing case" "$bin/opensees2fem" missing.toml -o out --time 1
expect 1 "mpm2cbgeo, missing particles" "$bin/mpm2cbgeo" "$case" missing.h5 -o out
for program in fem-solve fem2mpm mpm-solve slide-metrics slide-element opensees2fem mpm2cbgeo; do
  expect 2 "$program, unknown option" "$bin/$program" --no-such-option
done
expect 2 "slide-new-case, no name" "$source/tools/slide-new-case"
expect 1 "slide-new-case, missing folder" "$source/tools/slide-new-case" x missing-folder
[[ $failures == 0 ]] && echo "exit_status_test: ok"
exit $((failures > 0))
