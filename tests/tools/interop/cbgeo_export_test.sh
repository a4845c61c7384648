#!/usr/bin/env bash
# CB-Geo MPM export (tools/interop/README.md) on the elastic column of data/column:
#  1. its particle file (fem2mpm) and its mpm checkpoint after 0.5 s (moving particles,
#     strained) become CB-Geo input folders whose every file check_cbgeo_input.py reads
#     as CB-Geo's readers do and compares with the particles;
#  2. a frictional base becomes CB-Geo's friction constraint;
#  3. a particle outside the grid, or an end time before the particles' time, is a
#     one-line error with nothing written.
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

"$bin/mpm2cbgeo" -q "$data/case.toml" "$work/tt0/particles.h5" -o "$work/cbgeo-particles"
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
echo "cbgeo export: all checks passed"
