#!/usr/bin/env bash
# A restart continues the run its checkpoint came from (common/input/case_fingerprint.hpp):
# a case edited since in a part that changes the physics (here the Young's modulus, the
# damping, the grid's cell size) is refused in one line naming the part, before anything
# is written; --allow-changed PART lets it run with a warning; the end time may change
# freely. A restart with the case unchanged says nothing of changes (an MPM restart used to
# warn of a changed domain_min_x after shaking).
#
#   restart_change_test.sh SOURCE_DIR BIN SCRATCH
set -uo pipefail
src=$1
bin=$2
scratch=$3
rm -rf "$scratch" && mkdir -p "$scratch"
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
case_file=$scratch/case.toml
cp "$src/cases/column-short/case.toml" "$case_file"

# ---- fem-solve
"$bin/fem-solve" "$case_file" -o "$scratch/fem" --until 0.1 --checkpoint-every 0.05 --no-vtk -q ||
  fail "the first FE run"
restart() {  # restart PROGRAM FOLDER CHECKPOINT [options]: status, stderr in $scratch/err
  local program=$1 folder=$2 checkpoint=$3
  shift 3
  "$bin/$program" "$case_file" -o "$scratch/$folder" --restart "$checkpoint" --no-vtk -q "$@" \
    2> "$scratch/err"
}
sed -i 's/^youngs_modulus = 23.8e6/youngs_modulus = 30e6/' "$case_file"
restart fem-solve fem-e "$scratch/fem/fem_t0.050.h5" --until 0.1
status=$?
[[ $status -eq 1 ]] || fail "a changed Young's modulus: status $status"
grep -q "the case's materials changed since the checkpoint" "$scratch/err" ||
  fail "the part is not named: $(cat "$scratch/err")"
[[ $(wc -l < "$scratch/err") -eq 1 ]] || fail "not one line: $(cat "$scratch/err")"
[[ ! -e $scratch/fem-e ]] || fail "a refused restart wrote $(ls "$scratch/fem-e")"
restart fem-solve fem-e "$scratch/fem/fem_t0.050.h5" --until 0.1 --allow-changed materials ||
  fail "--allow-changed materials: $(cat "$scratch/err")"
grep -q "warning: .*materials changed since the checkpoint (--allow-changed materials)" \
  "$scratch/err" || fail "no warning with --allow-changed: $(cat "$scratch/err")"
sed -i 's/^youngs_modulus = 30e6/youngs_modulus = 23.8e6/' "$case_file"
sed -i 's/^rayleigh_stiffness = 0.005626/rayleigh_stiffness = 0.01/' "$case_file"
restart fem-solve fem-d "$scratch/fem/fem_t0.050.h5" --until 0.1
grep -q "the case's damping changed" "$scratch/err" || fail "damping: $(cat "$scratch/err")"
cp "$src/cases/column-short/case.toml" "$case_file"
restart fem-solve fem "$scratch/fem/fem_t0.050.h5" --until 0.12 ||
  fail "a restart to another end time: $(cat "$scratch/err")"
[[ ! -s $scratch/err ]] || fail "an unchanged case warned: $(cat "$scratch/err")"
restart fem-solve fem-x "$scratch/fem/fem_t0.050.h5" --until 0.1 --allow-changed density
grep -q "allow-changed density: not a part" "$scratch/err" || fail "an unknown part: $(cat "$scratch/err")"

# ---- mpm-solve, pure MPM
"$bin/mpm-solve" "$case_file" -o "$scratch/mpm" --until 0.02 --no-vtk -q || fail "the first MPM run"
checkpoint=$scratch/mpm/mpm_t0.000.h5
sed -i '/^\[mpm\]/,/^\[/ s/^cell_size = 1.0/cell_size = 0.5/' "$case_file"
restart mpm-solve mpm-h "$checkpoint" --until 0.02
grep -q "the case's grid changed" "$scratch/err" || fail "a changed cell size: $(cat "$scratch/err")"
cp "$src/cases/column-short/case.toml" "$case_file"
restart mpm-solve mpm "$checkpoint" --until 0.02 || fail "the MPM restart: $(cat "$scratch/err")"
[[ ! -s $scratch/err ]] || fail "an unchanged case warned: $(cat "$scratch/err")"

# ---- a shaken MPM run (slope-seismic): no warning of a moved grid
seismic=$src/cases/slope-seismic/case.toml
"$bin/mpm-solve" "$seismic" -o "$scratch/shaken" --until 0.3 --no-vtk -q ||
  fail "the shaken MPM run"
last=$(ls "$scratch"/shaken/mpm_t*.h5 | sort | tail -1)
"$bin/mpm-solve" "$seismic" -o "$scratch/shaken" --restart "$last" --until 0.4 --no-vtk -q \
  2> "$scratch/err" || fail "the shaken restart: $(cat "$scratch/err")"
[[ ! -s $scratch/err ]] || fail "the shaken restart warned: $(cat "$scratch/err")"

if ((failures > 0)); then echo "$failures failure(s)"; exit 1; fi
echo "restart_change_test: changed parts refused by name, allowed with a warning, no false warnings"
