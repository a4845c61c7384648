#!/usr/bin/env bash
# mpm-solve on 1, 2 and 3 ranks from the command line (tests/mpi/README.md):
#   - column-short from its geometry for 0.5 s (135 steps): the three checkpoints hold
#     the same particles, mass exact, momentum, energy and every particle field within
#     round-off (compare_by_id.py, 1e-10), in the serial build's layout;
#   - restart across rank counts: 1 rank to 0.3 s then 2 ranks to 0.5 s, and 3 ranks to
#     0.3 s then 1 rank to 0.5 s, each the same as the uninterrupted run;
#   - the 3-rank VTK frame: one .pvtu naming its three pieces, which VTK's parallel reader
#     reads as the 1-rank frame (every particle, the same fields within round-off);
#   - a damaged row in rank 1's part of a checkpoint, and a bad case file, on 2 ranks:
#     one error line (from the root only) and status 1.
# OpenMPI's mpirun (-q is its).
# Usage: ranks_test.sh BIN_DIR SOURCE_DIR WORK_DIR PYTHON MPIEXEC
set -euo pipefail
bin=$1 src=$2 work=$3 python=$4 mpiexec=$5
case_file=$src/cases/column-short/case.toml
compare=$src/tests/mpi/compare_by_id.py
rm -rf "$work" && mkdir -p "$work"

run() {  # run N OUT [mpm-solve options...]
  local n=$1 out=$2
  shift 2
  "$mpiexec" -n "$n" "$bin/mpm-solve" "$case_file" -o "$work/$out" --threads 1 -q "$@"
}

for n in 1 2 3; do run "$n" np$n --until 0.5 --vtk-every 0.5; done
"$python" "$compare" "$work/np1/mpm_final.h5" "$work/np2/mpm_final.h5"
"$python" "$compare" "$work/np1/mpm_final.h5" "$work/np3/mpm_final.h5"

run 1 first1 --until 0.3 --no-vtk
run 2 then2 --restart "$work/first1/mpm_final.h5" --until 0.5 --no-vtk
"$python" "$compare" "$work/np1/mpm_final.h5" "$work/then2/mpm_final.h5"
run 3 first3 --until 0.3 --no-vtk
run 1 then1 --restart "$work/first3/mpm_final.h5" --until 0.5 --no-vtk
"$python" "$compare" "$work/np1/mpm_final.h5" "$work/then1/mpm_final.h5"

# The last frame of the 3-rank run: a .pvtu of three pieces, which VTK's parallel reader
# (ParaView's) reads as the 1-rank frame: every particle once, the same fields, the same
# values within round-off once matched by id.
"$python" - "$work/np3/vtk" "$work/np1/vtk" <<'EOF'
import sys, pathlib, re
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
folder, serial = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
pvtu = sorted(folder.glob("mpm_*.pvtu"))[-1]
pieces = re.findall(r'<Piece Source="([^"]+)"', pvtu.read_text())
assert pieces == [f"{pvtu.stem}_r{r}.vtu" for r in range(3)], pieces

def read(reader, path):
    reader.SetFileName(str(path))
    reader.Update()
    data = reader.GetOutput().GetPointData()
    fields = {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i))
              for i in range(data.GetNumberOfArrays())}
    order = np.argsort(fields["id"])
    return {name: values[order] for name, values in fields.items()}

three = read(vtk.vtkXMLPUnstructuredGridReader(), pvtu)
one = read(vtk.vtkXMLUnstructuredGridReader(), serial / f"{pvtu.stem}.vtu")
assert sorted(three) == sorted(one), (sorted(three), sorted(one))
assert len(three["id"]) == 32000 and np.array_equal(three["id"], one["id"])
worst = max(np.abs(three[k] - one[k]).max() / max(np.abs(one[k]).max(), 1e-300) for k in one)
assert worst <= 1e-10, worst
print(f"{pvtu.name}: pieces {pieces}; VTK reads {len(three['id'])} points, "
      f"{len(three)} fields, within {worst:.2g} of the 1-rank frame")
EOF

# A checkpoint read in parts with a bad value in rank 1's rows only: every rank stops
# with the one line that names the row, status 1.
"$python" - "$work/np1/mpm_final.h5" "$work/damaged.h5" <<'PY'
import sys, shutil, h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    f["particles/mass"][30000] = float("nan")
PY
set +e
"$mpiexec" -q -n 2 "$bin/mpm-solve" "$case_file" -o "$work/damaged" --restart "$work/damaged.h5" \
  --no-vtk 2> "$work/damaged.err"
status=$?
set -e
expected="mpm-solve: error: $work/damaged.h5: /particles/mass: particle 30000 is not finite (nan)"
if [[ $status -ne 1 || $(wc -l < "$work/damaged.err") -ne 1 ]] ||
  [[ "$(cat "$work/damaged.err")" != "$expected" ]]; then
  echo "damaged row on rank 1: status $status, stderr:" >&2
  cat "$work/damaged.err" >&2
  exit 1
fi
echo "damaged row on rank 1: status 1, one line: $(cat "$work/damaged.err")"

# A case file that does not parse: one line from the root, status 1, on 2 ranks
# (mpirun's -q keeps its own notice about the non-zero status away).
printf '[case\nname = "broken"\n' > "$work/broken.toml"
set +e
"$mpiexec" -q -n 2 "$bin/mpm-solve" "$work/broken.toml" -o "$work/broken" 2> "$work/broken.err"
status=$?
set -e
lines=$(wc -l < "$work/broken.err")
if [[ $status -ne 1 || $lines -ne 1 ]] || ! grep -q '^mpm-solve: error: ' "$work/broken.err"; then
  echo "bad case on 2 ranks: status $status, $lines stderr lines:" >&2
  cat "$work/broken.err" >&2
  exit 1
fi
echo "bad case on 2 ranks: status 1, one line: $(cat "$work/broken.err")"
