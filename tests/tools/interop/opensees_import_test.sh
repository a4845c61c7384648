#!/usr/bin/env bash
# OpenSees import end to end (tools/interop/README.md), on the elastic column of
# data/column (its OpenSees script column.tcl, its files from make_recorders.py):
#  1. fem-solve computes the geostatic state from the OpenSees model (model.json);
#     opensees2fem imports the same state from the recorder files; the two checkpoints
#     agree dataset by dataset (compare_fem_checkpoints.py, 1e-9 of each dataset's scale);
#  2. fem2mpm and mpm-solve run from the imported checkpoint; the particles carry the
#     column's mass ρ W H = 4000 kg/m and σyy = −ρ g (H − y) at their places;
#  3. bad or inconsistent files end in one line naming the file (and the OpenSees tags at
#     fault) and a non-zero status, and write nothing; so do two --time values whose
#     checkpoints would share a name.
# Usage: opensees_import_test.sh SOURCE_DIR BIN_DIR WORK_DIR PYTHON
set -euo pipefail
source_dir=$1 bin=$2 work=$3 python=$4
data=$source_dir/tests/tools/interop/data/column
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin/fem-solve" -q "$data/case.toml" -o "$work/fem"
"$bin/opensees2fem" -q "$data/case.toml" -o "$work/import" --time 0 --time 0.02
"$python" "$source_dir/tests/tools/interop/compare_fem_checkpoints.py" \
  "$work/fem/fem_t0.000.h5" "$work/import/fem_t0.000.h5" || fail "import differs from fem-solve"
# The later row is the same state (the column stays at rest) at t = 0.02 s.
"$python" - "$work/import/fem_t0.020.h5" <<'PY' || fail "the t = 0.02 s import"
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    assert abs(f.attrs["time"] - 0.02) < 1e-15, f.attrs["time"]
    assert f.attrs["producer"].decode().startswith("opensees2fem (slide ")
    assert f["solver"].attrs["source"].decode() == "opensees"
    assert np.all(f["nodes/displacement"][...] == 0.0)
PY

"$bin/fem2mpm" -q "$work/import/fem_t0.000.h5" -o "$work/tt0/particles.h5" --case "$data/case.toml"
"$bin/mpm-solve" -q "$data/case.toml" -o "$work/tt0" --particles "$work/tt0/particles.h5"
"$python" - "$work/tt0/particles.h5" "$work/tt0/mpm_final.h5" <<'PY' || fail "the MPM chain"
import sys, h5py, numpy as np
rho, g, H = 2000.0, 9.81, 2.0
with h5py.File(sys.argv[1], "r") as f:
    mass = f["particles/mass"][...].sum()
    assert abs(mass - rho * 1.0 * H) < 1e-9 * rho, mass
    y = f["particles/coordinates"][:, 1]
    syy = f["particles/stress"][:, 1]
    # Element interpolation: each particle has its element's σyy, exact at mid-height,
    # so within ρ g h/2 of the closed form at the particle's own height.
    error = np.max(np.abs(syy + rho * g * (H - y)))
    assert error <= rho * g * 0.25 + 1e-6, error
with h5py.File(sys.argv[2], "r") as f:
    assert f.attrs["kind"].decode() == "mpm"
    assert abs(f["particles/mass"][...].sum() - rho * H) < 1e-9 * rho
print("particles: mass and stresses as the column's")
PY

# Bad input: one line, status 1, nothing written.
bad=$work/bad && mkdir -p "$bad"
expect_error() {  # expect_error PATTERN CASE_FILE [options...]
  local pattern=$1 case_file=$2
  shift 2
  local status=0
  "$bin/opensees2fem" "$case_file" -o "$bad/out" "$@" >"$bad/stdout" 2>"$bad/stderr" || status=$?
  [[ $status -eq 1 ]] || fail "status $status for $pattern"
  [[ $(wc -l <"$bad/stderr") -eq 1 ]] || fail "not one line: $(cat "$bad/stderr")"
  grep -q -- "$pattern" "$bad/stderr" || fail "expected '$pattern', got: $(cat "$bad/stderr")"
  [[ ! -e $bad/out ]] || fail "wrote $bad/out"
}
cp "$data"/* "$bad/"
# A time no recorder row has; the good time before it must not be written either.
expect_error "disp.out: no row at t = 0.3 s (the rows run from t = 0.5 to 0.02 s, 5 rows)" \
  "$bad/case.toml" --time 0 --time 0.3
# A node missing from the displacement recorder (its last two columns cut).
sed -i 's/ [^ ]* [^ ]*$//' "$bad/disp.out"
expect_error "disp.out:3: the row at t = 0 s has 28 values after the time, expected 30" \
  "$bad/case.toml" --time 0
cp "$data/disp.out" "$bad/"
# An element class the import does not read.
sed -i 's/"FourNodeQuad"/"nineNodeQuad"/' "$bad/model.json"
expect_error "model.json: element 1 is a nineNodeQuad, which the import does not read" \
  "$bad/case.toml" --time 0
cp "$data/model.json" "$bad/"
# A stress recorder of the wrong element count (the last element cut).
sed -i -E 's/( [^ ]+){12}$//' "$bad/stress.out"
expect_error "stress.out:3: the row at t = 0 s has 84 values after the time, expected 96" \
  "$bad/case.toml" --time 0
# Element 2 with its nodes clockwise: named by its tag and its nodes' (the mesh's index
# of the element is 1, of the node 1).
sed -i 's/"nodes": \[2, 3, 6, 5\]/"nodes": [2, 5, 6, 3]/' "$bad/model.json"
grep -qF '"nodes": [2, 5, 6, 3]' "$bad/model.json" || fail "the clockwise model was not made"
expect_error "model.json: element 2 (nodes 2 5 6 3) is inverted or has zero area: det J = -0.0625 at its node 2; expected its nodes counter-clockwise" \
  "$bad/case.toml" --time 0
cp "$data/model.json" "$bad/"
# Two times, one file name: fem_t0.020.h5 would hold only the second.
expect_error "--time: the checkpoint times 0.02 s and 0.0204 s would both be fem_t0.020.h5 (names have three decimals)" \
  "$bad/case.toml" --time 0.02 --time 0.0204
echo "opensees import: all checks passed"
