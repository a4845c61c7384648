#!/bin/sh
# A shaken run restarted from a checkpoint in the middle of the shaking continues bit for
# bit (docs/method.md §8): the motion, the boundary work and the recorders come back with
# the checkpoint. fem-solve on the compliant column (restart at 0.5 s, in the pulse's
# rise) and on the sliding block (restart at 0.8 s, sliding); mpm-solve on the sliding
# block from its t_T = 0 particles (restart at 1.0 s, after the main slip).
#   restart_test.sh BIN SOURCE_DIR WORK_DIR PYTHON
set -eu
bin=$1 src=$2 work=$3 python=$4
rm -rf "$work"
compare() {  # the end checkpoints and recorders of two runs
  for f in "$@"; do
    "$python" - "$f" "$(echo "$f" | sed 's|/whole/|/restarted/|')" <<'PY'
import sys, h5py, numpy as np
a, b = sys.argv[1], sys.argv[2]
if a.endswith(".csv"):
    ta, tb = open(a).read().splitlines(), open(b).read().splitlines()
    if ta != tb:
        sys.exit(f"{b}: {len(tb)} lines differ from {a} ({len(ta)} lines)")
    sys.exit(0)
fa, fb = h5py.File(a, "r"), h5py.File(b, "r")
for name in ("nodes/velocity", "nodes/displacement", "gauss_points/stress", "particles/velocity",
             "particles/coordinates", "particles/stress"):
    if name in fa:
        if not np.array_equal(fa[name][...], fb[name][...]):
            sys.exit(f"{b}: {name} differs from the uninterrupted run's")
for key in ("boundary_work",):
    if "solver" in fa and key in fa["solver"].attrs:
        if fa["solver"].attrs[key] != fb["solver"].attrs[key]:
            sys.exit(f"{b}: /solver {key} differs")
print(f"{b}: identical to the uninterrupted run")
PY
  done
}
column=$src/cases/column-seismic/compliant.toml
"$bin/fem-solve" "$column" -o "$work/column/whole" --no-vtk --until 1.5 --checkpoint-every 0.5
mkdir -p "$work/column/restarted"
# the restart's folder as the killed run left it: the checkpoint and a recorder file that
# runs past it (its rows after 0.5 s are dropped on resume)
cp "$work/column/whole/fem_t0.500.h5" "$work/column/restarted/"
cp -r "$work/column/whole/recorders" "$work/column/restarted/"
"$bin/fem-solve" "$column" -o "$work/column/restarted" --no-vtk --until 1.5 \
  --restart "$work/column/restarted/fem_t0.500.h5" --checkpoint-every 0.5
compare "$work/column/whole/fem_t1.500.h5" "$work/column/whole/recorders/surface.csv"

block=$src/tests/seismic/sliding-block/case.toml
"$bin/fem-solve" "$block" -o "$work/block/whole" --no-vtk
mkdir -p "$work/block/restarted"
cp "$work/block/whole/fem_t0.800.h5" "$work/block/restarted/"
cp -r "$work/block/whole/recorders" "$work/block/restarted/"
"$bin/fem-solve" "$block" -o "$work/block/restarted" --no-vtk --restart "$work/block/restarted/fem_t0.800.h5"
compare "$work/block/whole/fem_t2.500.h5" "$work/block/whole/recorders/block.csv"

"$bin/fem2mpm" "$work/block/whole/fem_t0.000.h5" -o "$work/mpm/particles.h5"
"$bin/mpm-solve" "$block" --particles "$work/mpm/particles.h5" -o "$work/mpm/whole" --no-vtk
"$bin/mpm-solve" "$block" --restart "$work/mpm/whole/mpm_t1.000.h5" -o "$work/mpm/restarted" --no-vtk
compare "$work/mpm/whole/mpm_final.h5"
