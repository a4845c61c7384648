#!/usr/bin/env bash
# CB-Geo MPM export (tools/interop/README.md) on the elastic column of data/column:
#  1. its particle file (fem2mpm) and its mpm checkpoint after 0.5 s (moving particles,
#     strained) become CB-Geo input folders whose every file check_cbgeo_input.py reads
#     as CB-Geo's readers do and compares with the particles;
#  2. a frictional base becomes CB-Geo's friction constraint;
#  3. what does not carry over is listed, one "not carried over:" line each: the defaults
#     of the column, and on the shaken 10° incline of tests/seismic/sliding-block its
#     gravity_angle and base motion (file's or case's), which mpm.json indeed lacks;
#  4. a particle outside the grid, an end time before the particles' time, a file of
#     another case (without --other-case), an output cadence shorter than the step or of
#     too many outputs, too many steps, a zero Courant number (status 2): a one-line error
#     with nothing written, and no mpm.json ever holds a null.
# Usage: cbgeo_export_test.sh SOURCE_DIR BIN_DIR WORK_DIR PYTHON
set -euo pipefail
source_dir=$1 bin=$2 work=$3 python=$4
here=$source_dir/tests/tools/interop
data=$here/data/column
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin/opensees2fem" -q "$data/case.toml" -o "$work/fem" --time 0
"$bin/fem2mpm" -q "$work/fem/fem_t0.000.h5" -o "$work/tt0/particles.h5" --case "$data/case.toml"
"$bin/mpm-solve" -q "$data/case.toml" -o "$work/tt0" --particles "$work/tt0/particles.h5"
check=("$python" "$here/check_cbgeo_input.py" --domain 0 0 1 3 --cell 0.25
  --boundary left=roller --boundary right=roller --boundary base=roller)

"$bin/mpm2cbgeo" "$data/case.toml" "$work/tt0/particles.h5" -o "$work/cbgeo-particles" \
  >"$work/column.log"
"${check[@]}" --end-time 0.5 "$work/tt0/particles.h5" "$work/cbgeo-particles"
"$bin/mpm2cbgeo" -q "$data/case.toml" "$work/tt0/mpm_final.h5" -o "$work/cbgeo-mpm" --end-time 1.5 \
  --output-every 0.3  # not a divisor of the 1 s: the export takes 0.25 s, so the end is written
"${check[@]}" --end-time 1.5 "$work/tt0/mpm_final.h5" "$work/cbgeo-mpm"
"$python" - "$work/tt0/mpm_final.h5" <<'PY' || fail "the mpm checkpoint should hold moving, strained particles"
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    assert np.abs(f["particles/velocity"][...]).max() > 0 and np.abs(f["particles/strain"][...]).max() > 0
PY
grep -q '"output_steps"' "$work/cbgeo-mpm/mpm.json" || fail "no output_steps"

# A frictional base.
awk '/^\[mpm\]$/ {print; print "friction_coefficient = 0.4"; next}
     /^\[mpm.boundaries\]$/ {mpm = 1}
     mpm && /^base = "roller"$/ {print "base = \"friction\""; next} {print}' \
  "$data/case.toml" >"$work/friction.toml"
cp "$data"/model.json "$data"/*.out "$work/"
"$bin/mpm2cbgeo" -q "$work/friction.toml" "$work/tt0/particles.h5" -o "$work/cbgeo-friction"
"$python" "$here/check_cbgeo_input.py" --domain 0 0 1 3 --cell 0.25 --boundary left=roller \
  --boundary right=roller --boundary base=friction --friction 0.4 --end-time 0.5 \
  "$work/tt0/particles.h5" "$work/cbgeo-friction"

# What does not carry over, one line each.
expect_note() {  # expect_note LOG TEXT
  grep -qF -- "mpm2cbgeo: not carried over: $2" "$1" || fail "no note '$2' in $1: $(cat "$1")"
}
expect_note "$work/column.log" "time step: mpm-solve's Courant step, renewed as the particles deform"
expect_note "$work/column.log" 'mpm.particle_exit = "freeze": CB-Geo removes the particles'
expect_note "$work/column.log" "mpm.speed_limit_factor = 5: CB-Geo has no instability guard"
! grep -qE "gravity_angle|base motion" "$work/column.log" || fail "notes of what the column lacks"
# The incline: gravity turned by 10°, shaken from t = 0.2 s; particles at t = 0.5 s.
incline=$source_dir/tests/seismic/sliding-block/incline.toml
"$bin/fem-solve" -q "$incline" -o "$work/incline/fem" --until 0.5 --no-vtk
"$bin/fem2mpm" -q "$work/incline/fem/fem_t0.500.h5" -o "$work/incline/particles.h5" --case "$incline"
"$bin/mpm2cbgeo" "$incline" "$work/incline/particles.h5" -o "$work/cbgeo-incline" \
  >"$work/incline.log"
expect_note "$work/incline.log" "gravity_angle: the case turns gravity by 10° to (1.70349, -9.66096) m/s²; mpm.json's gravity is (0, -9.81) m/s²"
expect_note "$work/incline.log" "base motion: the file's /motion ("
grep -qE "samples every [0-9.e+-]+ s from t = 0\.2 s, rigid base\) is not written: CB-Geo's grid stays at rest at mpm\.domain, while mpm-solve moves it with the base \(by \(0\.0[0-9]+, 0\) m at t = 0\.5 s\)" \
  "$work/incline.log" || fail "the base motion's note: $(cat "$work/incline.log")"
"$python" - "$work/cbgeo-incline/mpm.json" <<'PY' || fail "mpm.json should hold neither the turned gravity nor the motion"
import json, sys
mpm = json.load(open(sys.argv[1]))
assert mpm["external_loading_conditions"] == {"gravity": [0.0, -9.81]}, mpm["external_loading_conditions"]
assert "motion" not in json.dumps(mpm) and "acceleration_constraints" not in json.dumps(mpm)
PY
# The column's particles on the incline's grid: the case's [fem.motion], no /motion.
"$bin/mpm2cbgeo" "$incline" "$work/tt0/particles.h5" -o "$work/cbgeo-other" --other-case \
  >"$work/other.log" 2>"$work/other.err"
grep -qF 'particles.h5: written for case "opensees-column", exported with case "sliding-block" (--other-case)' \
  "$work/other.err" || fail "no --other-case warning: $(cat "$work/other.err")"
expect_note "$work/other.log" "base motion: the case's [fem.motion] is not written (the particle file has no /motion either)"
for folder in cbgeo-particles cbgeo-mpm cbgeo-friction cbgeo-incline cbgeo-other; do
  ! grep -qw null "$work/$folder/mpm.json" || fail "$folder/mpm.json holds a null"
done

# Bad input: one line, status 1, nothing written.
expect_error() {  # expect_error PATTERN ARGS...
  local pattern=$1
  shift
  local status=0
  "$bin/mpm2cbgeo" "$@" -o "$work/bad" >"$work/stdout" 2>"$work/stderr" || status=$?
  [[ $status -eq 1 ]] || fail "status $status for $pattern"
  [[ $(wc -l <"$work/stderr") -eq 1 ]] || fail "not one line: $(cat "$work/stderr")"
  grep -qF -- "$pattern" "$work/stderr" || fail "expected '$pattern', got: $(cat "$work/stderr")"
  [[ ! -e $work/bad ]] || fail "wrote $work/bad"
}
sed 's/^domain = \[\[0.0, 0.0\], \[1.0, 3.0\]\]$/domain = [[0.0, 0.0], [1.0, 1.5]]/' \
  "$work/friction.toml" >"$work/small.toml"
grep -q '1.0, 1.5' "$work/small.toml" || fail "the small-grid case was not made"
expect_error "is outside the grid (0, 0)–(1, 1.5) m of the case's mpm.domain: CB-Geo cannot locate it" \
  "$work/small.toml" "$work/tt0/particles.h5"
expect_error "end time 0.25 s is not after the particles' time 0.5 s (give --end-time)" \
  "$data/case.toml" "$work/tt0/mpm_final.h5" --end-time 0.25
expect_error "particles.h5: written for case \"opensees-column\", not for case \"sliding-block\" of $incline (--other-case to export it anyway)" \
  "$incline" "$work/tt0/particles.h5"
expect_error "--output-every = 1e-300 s is shorter than CB-Geo's time step 0.000114109 s" \
  "$data/case.toml" "$work/tt0/particles.h5" --output-every 1e-300
expect_error "--output-every = 0.0002 s makes 5e+05 outputs over the 100 s from t = 0 to 100 s, more than 1e+05" \
  "$data/case.toml" "$work/tt0/particles.h5" --end-time 100 --output-every 0.0002
expect_error "the run would take 8.76e+303 steps of 0.000114 s (at most 1e+09)" \
  "$data/case.toml" "$work/tt0/particles.h5" --end-time 1e300
# A zero Courant number is the command line's fault: status 2.
status=0
"$bin/mpm2cbgeo" "$data/case.toml" "$work/tt0/particles.h5" -o "$work/bad" --courant 0 \
  >"$work/stdout" 2>"$work/stderr" || status=$?
[[ $status -eq 2 && $(wc -l <"$work/stderr") -eq 1 && ! -e $work/bad ]] ||
  fail "--courant 0: status $status, $(cat "$work/stderr")"
grep -qF -- "--courant: must be > 0, got 0" "$work/stderr" || fail "--courant 0: $(cat "$work/stderr")"
echo "cbgeo export: all checks passed"
